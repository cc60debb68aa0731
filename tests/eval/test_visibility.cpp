// Visible surface: field of view and line of sight (shadowed faces excluded).
#include <gtest/gtest.h>

#include "eval_test_helpers.hpp"
#include "ground_truth.hpp"
#include "visibility.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(SensorFov, FlsFanFromGeometry) {
    const SensorFov fov = SensorFov::fls(FlsGeometry{});
    const auto at = [](double range, double bearing_deg, double elevation_deg) {
        const double b = bearing_deg * kDeg, e = elevation_deg * kDeg;
        return Eigen::Vector3d(range * std::cos(e) * std::cos(b), range * std::cos(e) * std::sin(b), range * std::sin(e));
    };
    EXPECT_TRUE(fov.contains(at(5.0, 0.0, 40.0)));
    EXPECT_TRUE(fov.contains(at(5.0, 14.0, 46.0)));
    EXPECT_FALSE(fov.contains(at(5.0, 15.0, 40.0)));   // outside +-14.5 deg
    EXPECT_FALSE(fov.contains(at(5.0, 0.0, 30.0)));    // above 40-7 deg
    EXPECT_FALSE(fov.contains(at(10.5, 0.0, 40.0)));   // beyond max range
    EXPECT_FALSE(fov.contains(at(0.5, 0.0, 40.0)));    // inside min range
    const SensorFov ps = SensorFov::ps(PsGeometry{});
    EXPECT_TRUE(ps.contains(at(5.0, 9.0, 21.0)));
    EXPECT_FALSE(ps.contains(at(5.0, 11.0, 40.0)));
}

SensorRun omnidirectional(const Eigen::Vector3d& at) {
    return {"all", {-M_PI, M_PI, -M_PI / 2, M_PI / 2, 0.0, 100.0}, {{at, Eigen::Matrix3d::Identity()}}};
}

class BoxOnSeabed : public ::testing::Test {
protected:
    void SetUp() override {
        box_ = loadMesh(test::writeBox("vis_box", {0.0, 0.0, 19.0}, {2.0, 1.2, 20.0}));
        seabed_ = loadMesh(test::writeOff("vis_seabed", {{-5, -5, 20.0}, {5, -5, 20.0}, {5, 5, 20.0}, {-5, 5, 20.0}},
                                          {{0, 1, 2, 3}}));
        grid_ = GridSpec{Eigen::Vector3d(-1.0, -1.0, 18.0), 0.1, 40, 30, 25};
        truth_ = voxeliseMesh(box_, grid_);
    }
    VoxelMask visibleFrom(const Eigen::Vector3d& sensor) const {
        const auto samples = sampleVisibleSurface({box_}, {box_, seabed_}, {omnidirectional(sensor)});
        return markVisibleVoxels(grid_, truth_.surface, samples, 1u);
    }
    bool at(const VoxelMask& m, const Eigen::Vector3d& p) const {
        const Eigen::Vector3d c = grid_.toCell(p);
        return m[grid_.linear(static_cast<int>(c.x()), static_cast<int>(c.y()), static_cast<int>(c.z()))] != 0;
    }
    TriangleMesh box_, seabed_;
    GridSpec grid_;
    MeshVoxels truth_;
};

TEST_F(BoxOnSeabed, FrontAndTopSeenBackAndBottomShadowed) {
    // In front of the x=0 face, above the top (z=19): sees front and top only.
    const VoxelMask seen = visibleFrom({-3.0, 0.6, 18.0});
    EXPECT_TRUE(at(seen, {0.05, 0.55, 19.55}));   // front face
    EXPECT_TRUE(at(seen, {1.05, 0.55, 19.05}));   // top face
    EXPECT_FALSE(at(seen, {1.95, 0.55, 19.55}));  // back face: shadowed by the box
    EXPECT_FALSE(at(seen, {1.05, 0.55, 19.95}));  // bottom: on the seabed, never seen
    // Side faces y=0 / y=1.2 are seen edge-on from y=0.6: not seen (except voxels shared with front/top).
    EXPECT_FALSE(at(seen, {1.05, 0.05, 19.55}));
    // Visible = front face (12*10) + top (20*12) - shared edge row (12) = 348.
    EXPECT_EQ(countSet(seen), 348u);
}

// A box sunk 0.2 m into the seabed: the buried part of the front face is not seen.
TEST_F(BoxOnSeabed, SeabedHidesTheBuriedBase) {
    seabed_ = loadMesh(test::writeOff("vis_seabed_high", {{-5, -5, 19.8}, {5, -5, 19.8}, {5, 5, 19.8}, {-5, 5, 19.8}},
                                      {{0, 1, 2, 3}}));
    const VoxelMask seen = visibleFrom({-3.0, 0.6, 18.0});
    EXPECT_TRUE(at(seen, {0.05, 0.55, 19.75}));
    EXPECT_FALSE(at(seen, {0.05, 0.55, 19.85}));
    // Front face rows 19.0..19.8 (8 * 12) + top (240) - shared edge row (12).
    EXPECT_EQ(countSet(seen), 324u);
}

TEST_F(BoxOnSeabed, OutOfRangeSeesNothing) {
    SensorRun run = omnidirectional({-3.0, 0.6, 18.0});
    run.fov.range_max = 2.0;
    const auto samples = sampleVisibleSurface({box_}, {box_, seabed_}, {run});
    for (const auto& s : samples) EXPECT_EQ(s.seen_by, 0u);
}

// Only the surface within some pose's range is sampled: the same samples
// seen, in the same order, as when every triangle is sampled whole, and a
// mesh far larger than the survey costs only the part of it within reach.
TEST_F(BoxOnSeabed, OnlyTheSurfaceWithinReachIsSampled) {
    SensorRun near = omnidirectional({-3.0, 0.6, 18.0});
    near.fov.range_max = 3.5;  // reaches x <= 0.5: the box (x 0..2) is cut
    // A second run whose reach covers everything, so nothing is cut (its own bit is not compared).
    SensorRun far = omnidirectional({3000.0, 0.0, 0.0});
    far.fov.range_max = 4000.0;
    const auto cut = sampleVisibleSurface({box_}, {box_, seabed_}, {near});
    const auto whole = sampleVisibleSurface({box_}, {box_, seabed_}, {near, far});
    EXPECT_LT(cut.size(), whole.size() / 2);
    std::vector<Eigen::Vector3d> seen_cut, seen_whole;
    for (const auto& s : cut)
        if (s.seen_by & 1u) seen_cut.push_back(s.point);
    for (const auto& s : whole)
        if (s.seen_by & 1u) seen_whole.push_back(s.point);
    EXPECT_GT(seen_cut.size(), 100u);
    EXPECT_EQ(seen_cut, seen_whole);

    // A 20 km square object (a mesh in millimetres left unscaled): about 6e11
    // samples whole; within the 7 m reach, the part the run can see.
    const TriangleMesh huge = loadMesh(test::writeOff(
        "vis_huge", {{-1e4, -1e4, 19.5}, {1e4, -1e4, 19.5}, {1e4, 1e4, 19.5}, {-1e4, 1e4, 19.5}}, {{0, 1, 2, 3}}));
    const auto samples = sampleVisibleSurface({huge}, {huge}, {near});
    EXPECT_GT(samples.size(), 10000u);
    EXPECT_LT(samples.size(), 1000000u);
    std::size_t seen = 0;
    for (const auto& s : samples) seen += s.seen_by != 0;
    EXPECT_GT(seen, 10000u);
}

// Two passes in opposite directions see both end faces.
TEST_F(BoxOnSeabed, TwoRunsBitsAndUnion) {
    const auto samples = sampleVisibleSurface({box_}, {box_, seabed_},
                                              {omnidirectional({-3.0, 0.6, 18.0}), omnidirectional({5.0, 0.6, 18.0})});
    const VoxelMask first = markVisibleVoxels(grid_, truth_.surface, samples, 1u);
    const VoxelMask second = markVisibleVoxels(grid_, truth_.surface, samples, 2u);
    const VoxelMask both = markVisibleVoxels(grid_, truth_.surface, samples, 3u);
    EXPECT_TRUE(at(second, {1.95, 0.55, 19.55}));
    EXPECT_FALSE(at(second, {0.05, 0.55, 19.55}));
    EXPECT_EQ(countSet(both), 348u + 120u - 12u);  // + the back face, whose top row is already in
    EXPECT_EQ(countSet(first), 348u);
}

}  // namespace
}  // namespace sonarfusion::eval
