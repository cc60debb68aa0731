#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "sonarfusion/fls_update.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {
constexpr double kDeg = M_PI / 180.0;

struct Fixture {
    FlsGeometry geom;
    FlsModel model{geom};
    UpdateConfig cfg;
    VoxelMap map{MapConfig{}};
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();

    Fixture() {
        // Map centred 4 m ahead and 3 m below a sensor at the world origin.
        map.initialiseAt(Eigen::Vector3d(4.0, 0.0, 3.0));
    }
    // The voxel of Eq. 4 computed here with explicit trig, independent of the model's tables.
    std::size_t expectedVoxel(int row, int col, int k) const {
        const double r = 0.83 + (511.0 - row) / 511.0 * 9.17;
        const double th = 29.0 * kDeg * (col - 48.0) / 96.0;
        const double down = 40.0 * kDeg + (-7.0 + 3.5 * k) * kDeg;
        const Eigen::Vector3d p(r * std::cos(down) * std::cos(th), r * std::cos(down) * std::sin(th), r * std::sin(down));
        VoxelIndex v;
        EXPECT_TRUE(map.worldToIndex(sensor * p, v));
        return map.linear(v);
    }
};

int countNonZero(const VoxelMap& m) {
    int n = 0;
    for (std::size_t i = 0; i < m.size(); ++i) n += m.logOdds(i) != 0.0f;
    return n;
}
}  // namespace

TEST(FlsUpdate, OnePixelRaisesExactlyTheNvVoxelsByEq6) {
    Fixture fx;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    const int row = 200, col = 60;
    test::setPixel(frame, row, col, 204);
    const FlsUpdateStats st = up.apply(frame.view, fx.sensor, fx.map);
    EXPECT_EQ(st.pixels_above_threshold, 1);
    EXPECT_EQ(st.points_in_map, 5);
    EXPECT_EQ(st.voxels_updated, 5);

    const float expected = static_cast<float>(std::log(0.7 / 0.3) * 0.3 * 204.0 / 255.0);
    std::set<std::size_t> want;
    for (int k = 0; k < 5; ++k) want.insert(fx.expectedVoxel(row, col, k));
    ASSERT_EQ(want.size(), 5u) << "the five elevation samples should fall in five voxels at this range";
    for (std::size_t v : want) EXPECT_NEAR(fx.map.logOdds(v), expected, 1e-6);
    EXPECT_EQ(countNonZero(fx.map), 5);
}

TEST(FlsUpdate, ThresholdIsStrictlyAbove150) {
    Fixture fx;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    test::setPixel(frame, 200, 40, 150);
    EXPECT_EQ(up.apply(frame.view, fx.sensor, fx.map).pixels_above_threshold, 0);
    EXPECT_EQ(countNonZero(fx.map), 0);
    test::setPixel(frame, 200, 40, 151);
    EXPECT_EQ(up.apply(frame.view, fx.sensor, fx.map).pixels_above_threshold, 1);
}

TEST(FlsUpdate, OncePerFrameKeepsTheStrongestIntensity) {
    Fixture fx;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    // Adjacent range rows (1.8 cm apart) fall into the same 10 cm voxels.
    test::setPixel(frame, 300, 48, 160);
    test::setPixel(frame, 301, 48, 240);
    ASSERT_EQ(fx.expectedVoxel(300, 48, 2), fx.expectedVoxel(301, 48, 2));
    up.apply(frame.view, fx.sensor, fx.map);
    const float once = static_cast<float>(std::log(0.7 / 0.3) * 0.3 * 240.0 / 255.0);
    EXPECT_NEAR(fx.map.logOdds(fx.expectedVoxel(301, 48, 2)), once, 1e-6);
}

TEST(FlsUpdate, PaperModeCountsEveryPixelPoint) {
    Fixture fx;
    fx.cfg.fls_once_per_frame = false;
    fx.cfg.alpha_fls = 1.0;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    test::setPixel(frame, 300, 48, 160);
    test::setPixel(frame, 301, 48, 240);
    up.apply(frame.view, fx.sensor, fx.map);
    const float both = static_cast<float>(std::log(0.7 / 0.3) * (160.0 + 240.0) / 255.0);
    EXPECT_NEAR(fx.map.logOdds(fx.expectedVoxel(301, 48, 2)), both, 1e-5);
}

TEST(FlsUpdate, RepeatedFramesSaturateAtPlusFive) {
    Fixture fx;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    test::setPixel(frame, 250, 30, 255);
    for (int i = 0; i < 100; ++i) up.apply(frame.view, fx.sensor, fx.map);
    EXPECT_FLOAT_EQ(fx.map.logOdds(fx.expectedVoxel(250, 30, 0)), 5.0f);
    // And the per-frame scratch was cleared each time: a fresh frame still counts.
    EXPECT_EQ(countNonZero(fx.map), 5);
}

TEST(FlsUpdate, VehiclePoseMovesThePoints) {
    Fixture fx;
    Pose p;
    p.position = Eigen::Vector3d(1.0, 0.5, 0.0);
    p.yaw = 10 * kDeg;
    fx.sensor = sensorToWorld(p, Mounting{});
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    test::setPixel(frame, 260, 20, 200);
    up.apply(frame.view, fx.sensor, fx.map);
    for (int k = 0; k < 5; ++k) EXPECT_GT(fx.map.logOdds(fx.expectedVoxel(260, 20, k)), 0.0f);
}

TEST(FlsUpdate, PointsOutsideTheMapAreCountedNotWritten) {
    Fixture fx;
    fx.map.initialiseAt(Eigen::Vector3d(500.0, 0.0, 0.0));  // far away from the sensor
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    for (int c = 0; c < 96; ++c) test::setPixel(frame, 10, c, 255);
    const FlsUpdateStats st = up.apply(frame.view, fx.sensor, fx.map);
    EXPECT_EQ(st.points_outside_map, 96 * 5);
    EXPECT_EQ(st.points_in_map, 0);
    EXPECT_EQ(countNonZero(fx.map), 0);
}
