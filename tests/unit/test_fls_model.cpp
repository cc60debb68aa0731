#include <gtest/gtest.h>

#include <cmath>

#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/pose.hpp"

using namespace sonarfusion;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST(FlsModel, RowZeroIsFarRange) {  // Eq. 1
    FlsModel m{FlsGeometry{}};
    EXPECT_DOUBLE_EQ(m.rangeOfRow(0), 10.0);
    EXPECT_DOUBLE_EQ(m.rangeOfRow(511), 0.83);
    EXPECT_NEAR(m.rangeOfRow(1), 10.0 - 9.17 / 511.0, 1e-12);
    EXPECT_GT(m.rangeOfRow(100), m.rangeOfRow(101));
}

TEST(FlsModel, CentreColumnIsBearingZeroAndColumnZeroIsPort) {  // Eq. 2
    FlsModel m{FlsGeometry{}};
    EXPECT_DOUBLE_EQ(m.bearingOfColumn(48), 0.0);
    EXPECT_NEAR(m.bearingOfColumn(0), -14.5 * kDeg, 1e-12);
    EXPECT_NEAR(m.bearingOfColumn(95), 29.0 * kDeg * 47.0 / 96.0, 1e-12);
    // Port is -y in the FRD body frame.
    EXPECT_LT(m.direction(0, 2).y(), 0.0f);
    EXPECT_GT(m.direction(95, 2).y(), 0.0f);
}

TEST(FlsModel, ElevationSamplesSpanTheVerticalAperture) {  // Eq. 3
    FlsModel m{FlsGeometry{}};
    EXPECT_NEAR(m.elevationOfSample(0), -7.0 * kDeg, 1e-12);
    EXPECT_NEAR(m.elevationOfSample(2), 0.0, 1e-12);
    EXPECT_NEAR(m.elevationOfSample(4), 7.0 * kDeg, 1e-12);
}

TEST(FlsModel, HandComputedPointsTiltLooksDown) {  // Eq. 4
    FlsModel m{FlsGeometry{}};
    // Nearest row, centre beam, centre elevation: r = 0.83 along the 40 deg tilt.
    Eigen::Vector3d p = m.pointInSensor(511, 48, 2);
    EXPECT_NEAR(p.x(), 0.83 * std::cos(40 * kDeg), 1e-6);
    EXPECT_NEAR(p.y(), 0.0, 1e-6);
    EXPECT_NEAR(p.z(), 0.83 * std::sin(40 * kDeg), 1e-6);  // z down: positive below the sensor
    EXPECT_GT(p.z(), 0.0);
    // Far row, port edge beam, lower elevation edge (47 deg down).
    p = m.pointInSensor(0, 0, 4);
    const double down = 47 * kDeg, th = -14.5 * kDeg;
    EXPECT_NEAR(p.x(), 10.0 * std::cos(down) * std::cos(th), 1e-5);
    EXPECT_NEAR(p.y(), 10.0 * std::cos(down) * std::sin(th), 1e-5);
    EXPECT_NEAR(p.z(), 10.0 * std::sin(down), 1e-5);
    // The k = 0 sample (33 deg) is shallower than k = 4 (47 deg).
    EXPECT_LT(m.pointInSensor(0, 48, 0).z(), m.pointInSensor(0, 48, 4).z());
}

TEST(FlsModel, NonUniformTablesAreUsedAsGiven) {
    FlsGeometry g;
    g.beams = 3;
    g.rows = 4;
    g.beam_bearing = {-0.2, 0.05, 0.3};
    g.row_range = {9.0, 6.0, 2.0, 1.0};
    FlsModel m{g};
    EXPECT_DOUBLE_EQ(m.bearingOfColumn(1), 0.05);
    EXPECT_DOUBLE_EQ(m.rangeOfRow(2), 2.0);
}

TEST(FlsModel, RejectsImpossibleGeometry) {
    FlsGeometry g;
    g.range_max = 0.5;  // below range_min
    EXPECT_THROW(FlsModel{g}, std::invalid_argument);
    g = FlsGeometry{};
    g.beam_bearing = {0.1, 0.2};  // wrong size
    EXPECT_THROW(FlsModel{g}, std::invalid_argument);
    g = FlsGeometry{};
    g.rows = 1;
    EXPECT_THROW(FlsModel{g}, std::invalid_argument);
}

TEST(FlsModel, FrameMustMatchGeometry) {
    FlsModel m{FlsGeometry{}};
    std::vector<uint8_t> buf(512 * 96);
    FlsFrame f{0, 512, 96, buf.data(), buf.size()};
    EXPECT_TRUE(m.frameMatches(f));
    f.rows = 511;
    EXPECT_FALSE(m.frameMatches(f));
    f = FlsFrame{0, 512, 96, buf.data(), buf.size() - 1};
    EXPECT_FALSE(m.frameMatches(f));
    f = FlsFrame{0, 512, 96, nullptr, buf.size()};
    EXPECT_FALSE(m.frameMatches(f));
}

// Issue 11: the candidate points follow the full NAV attitude. Hand-computed
// for the centre beam (bearing 0) at centre elevation, 40 deg below the bow.
TEST(FlsModel, PitchAndRollMoveCandidatePointsWhereGeometrySays) {
    FlsModel m{FlsGeometry{}};
    const double r = m.rangeOfRow(0);  // 10 m
    Pose nose_up;
    nose_up.position = Eigen::Vector3d(1.0, 2.0, 3.0);
    nose_up.pitch = 5 * kDeg;  // nose up: the beam looks 35 deg down
    Eigen::Vector3d p = sensorToWorld(nose_up, Mounting{}) * m.pointInSensor(0, 48, 2);
    EXPECT_NEAR(p.x(), 1.0 + r * std::cos(35 * kDeg), 1e-5);
    EXPECT_NEAR(p.y(), 2.0, 1e-5);
    EXPECT_NEAR(p.z(), 3.0 + r * std::sin(35 * kDeg), 1e-5);
    // Rolled 10 deg starboard down: the belly turns to port, so a point below
    // the bow swings to port (-y) and rises a little: y = -sin(10) r sin(40),
    // z = cos(10) r sin(40); x unchanged.
    Pose rolled;
    rolled.roll = 10 * kDeg;
    p = sensorToWorld(rolled, Mounting{}) * m.pointInSensor(0, 48, 2);
    EXPECT_NEAR(p.x(), r * std::cos(40 * kDeg), 1e-5);
    EXPECT_NEAR(p.y(), -std::sin(10 * kDeg) * r * std::sin(40 * kDeg), 1e-5);
    EXPECT_NEAR(p.z(), std::cos(10 * kDeg) * r * std::sin(40 * kDeg), 1e-5);
    // Yawed 90 deg (heading east) and pitched: the same depression, now along +y.
    Pose east = nose_up;
    east.yaw = 90 * kDeg;
    p = sensorToWorld(east, Mounting{}) * m.pointInSensor(0, 48, 2);
    EXPECT_NEAR(p.x(), 1.0, 1e-5);
    EXPECT_NEAR(p.y(), 2.0 + r * std::cos(35 * kDeg), 1e-5);
    EXPECT_NEAR(p.z(), 3.0 + r * std::sin(35 * kDeg), 1e-5);
}
