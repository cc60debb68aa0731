// FLS geometry: echoes where Eqs. 1-4 put them, objects at their bearing and
// range, nothing past the maximum range, shadows behind objects.
#include <gtest/gtest.h>

#include <cmath>

#include "sim_test_util.hpp"
#include "simulator.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;
using test::TinyScenario;

// Rows of one column holding an echo (noise is off in these tests, so any
// non-zero count is an echo).
std::vector<int> echoRows(const FlsImage& img, int col) {
    std::vector<int> rows;
    for (int r = 0; r < img.rows; ++r)
        if (img.at(r, col) > 0) rows.push_back(r);
    return rows;
}

class FlsSimTest : public ::testing::Test {
protected:
    Simulator make(TinyScenario t) { return Simulator(loadScenarioFromString(t.yaml(), dir.path())); }
    TempDir dir;
};

TEST_F(FlsSimTest, FlatSeabedEchoesAtPredictedRangesInCentreBeam) {
    saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
    TinyScenario t;
    t.meshes = "- {file: plane.obj, role: seabed}\n";
    t.altitude = 3.0;
    const Simulator sim = make(t);
    const SequenceState& q = sim.sequences().front();
    const FlsImage img = sim.fls().render(q.pose, q.index);
    const FlsModel& m = sim.fls().model();
    const int centre = m.cols() / 2;
    ASSERT_NEAR(m.bearingOfColumn(centre), 0.0, 1e-12);
    const auto rows = echoRows(img, centre);
    ASSERT_FALSE(rows.empty());
    // Eq. 4: a ray at elevation phi meets a flat seabed h below at h / sin(tilt + phi).
    const double bin = (m.rangeOfRow(0) - m.rangeOfRow(m.rows() - 1)) / (m.rows() - 1);
    const double near = 3.0 / std::sin(40.0 * kDegToRad + 7.0 * kDegToRad);
    const double far = 3.0 / std::sin(40.0 * kDegToRad - 7.0 * kDegToRad);
    EXPECT_NEAR(m.rangeOfRow(rows.back()), near, bin);   // highest row index = nearest range
    EXPECT_NEAR(m.rangeOfRow(rows.front()), far, bin);
    // Contiguous: every range bin between the two edges is lit.
    EXPECT_EQ(static_cast<int>(rows.size()), rows.back() - rows.front() + 1);
    // The water in front of and beyond the seabed band stays black.
    EXPECT_EQ(img.at(m.rows() - 1, centre), 0);
    EXPECT_EQ(img.at(0, centre), 0);
}

TEST_F(FlsSimTest, BoxAppearsAtItsBearingAndRange) {
    // No seabed: a 0.3 m cube alone, 5 m away at bearing +8 deg on the boresight cone.
    const double range = 5.0, bearing = 8.0 * kDegToRad, down = 40.0 * kDegToRad;
    const double altitude = 3.0, vehicle_z = 20.0 - altitude, h = 0.15;
    const Eigen::Vector3d c(range * std::cos(down) * std::cos(bearing), range * std::cos(down) * std::sin(bearing),
                            range * std::sin(down));  // relative to the sonar
    saveObj(test::box(c.x(), c.y(), vehicle_z + c.z(), h, h, h), dir.file("cube.obj"));
    TinyScenario t;
    t.meshes = "- {file: cube.obj, role: object}\n";
    t.altitude = altitude;
    const Simulator sim = make(t);
    const SequenceState& q = sim.sequences().front();
    const FlsImage img = sim.fls().render(q.pose, q.index);
    const FlsModel& m = sim.fls().model();

    double weight = 0.0, weighted_bearing = 0.0, nearest = 1e9, farthest = 0.0;
    for (int c = 0; c < img.cols; ++c) {
        for (int r : echoRows(img, c)) {
            weight += img.at(r, c);
            weighted_bearing += img.at(r, c) * m.bearingOfColumn(c);
            nearest = std::min(nearest, m.rangeOfRow(r));
            farthest = std::max(farthest, m.rangeOfRow(r));
        }
    }
    ASSERT_GT(weight, 0.0);
    const double beam = 29.0 * kDegToRad / 96;
    EXPECT_NEAR(weighted_bearing / weight, bearing, 1.5 * beam);
    // The sonar sees the cube's front (-x), top (-z) and port (-y) faces: the
    // nearest point is their common corner, the farthest the far corner of the
    // port face; the three hidden faces never echo.
    const double bin = (m.rangeOfRow(0) - m.rangeOfRow(m.rows() - 1)) / (m.rows() - 1);
    EXPECT_NEAR(nearest, (c - Eigen::Vector3d(h, h, h)).norm(), 2 * bin);
    EXPECT_NEAR(farthest, (c + Eigen::Vector3d(h, -h, h)).norm(), 2 * bin);
}

TEST_F(FlsSimTest, ReturnsPastMaxRangeAreDroppedNotWrapped) {
    // Seabed 6.5 m below: the aperture meets it at 8.9..11.9 m, beyond 10 m in part.
    saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
    TinyScenario t;
    t.meshes = "- {file: plane.obj, role: seabed}\n";
    t.altitude = 6.5;
    const Simulator sim = make(t);
    const SequenceState& q = sim.sequences().front();
    const FlsImage img = sim.fls().render(q.pose, q.index);
    const FlsModel& m = sim.fls().model();
    const double near = 6.5 / std::sin(47.0 * kDegToRad);
    for (int c = 0; c < img.cols; c += 7) {
        const auto rows = echoRows(img, c);
        ASSERT_FALSE(rows.empty());
        EXPECT_EQ(rows.front(), 0) << "echoes continue up to the last (farthest) row";
        EXPECT_GT(m.rangeOfRow(rows.back()), near - 0.05) << "nothing wrapped to short range";
    }
    // Deeper still: nothing at all.
    t.altitude = 8.0;
    const Simulator deep = make(t);
    const FlsImage empty = deep.fls().render(deep.sequences().front().pose, 0);
    for (uint8_t v : empty.data) ASSERT_EQ(v, 0);
}

TEST_F(FlsSimTest, ObjectCastsShadowOnSeabed) {
    // A 0.6 m tall block on the seabed, 4.3 m ahead: the seabed just behind it
    // (in range, same beams) is hidden.
    saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
    saveObj(test::box(3.3, 0.0, 19.7, 0.2, 0.5, 0.3), dir.file("block.obj"));
    TinyScenario t;
    t.meshes = "- {file: plane.obj, role: seabed}\n- {file: block.obj, role: object}\n";
    t.altitude = 3.0;
    const Simulator sim = make(t);
    const FlsImage img = sim.fls().render(sim.sequences().front().pose, 0);
    const FlsModel& m = sim.fls().model();
    const int centre = m.cols() / 2;
    // Flat seabed would be lit all the way to 3 / sin(33 deg) = 5.5 m; behind
    // the block's top edge the centre beam must go dark before that.
    const auto rows = echoRows(img, centre);
    ASSERT_FALSE(rows.empty());
    int gaps = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) gaps += rows[i - 1] + 1 != rows[i];
    EXPECT_GE(gaps, 1) << "expected a shadow gap in the centre beam";
    EXPECT_EQ(echoRows(img, 0).size() > 0, true);  // beams beside the block still see seabed
}

TEST_F(FlsSimTest, ThreadCountDoesNotChangeTheBytes) {
    saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
    TinyScenario t;
    t.meshes = "- {file: plane.obj, role: seabed}\n";
    t.noise = "{speckle: true, floor: 10}";
    const Simulator sim = make(t);
    const SequenceState& q = sim.sequences().front();
    EXPECT_EQ(sim.fls().render(q.pose, q.index, 1).data, sim.fls().render(q.pose, q.index, 3).data);
}

}  // namespace
}  // namespace sonarfusion::sim
