#include <gtest/gtest.h>

#include <cmath>

#include "sonarfusion/ps_carving.hpp"
#include "sonarfusion/variant.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {
// A single-ray PS looking straight along +x: tilt 0, head 0, fan of one sample.
PsGeometry singleRay() {
    PsGeometry g;
    g.fan_samples = 1;
    g.fan_min = g.fan_max = 0.0;
    g.tilt = 0.0;
    return g;
}
}  // namespace

TEST(PsCarving, TouchesEveryVoxelOnTheRayButTheEndWithFallingWeights) {
    VoxelMap map = test::originMap();
    PsModel model{singleRay()};
    UpdateConfig cfg;
    cfg.ps_endpoint_hits = false;  // Eq. 13 alone (the paper variant)
    PsCarver carver(model, cfg);
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.translation() = Eigen::Vector3d(1.05, 2.05, 3.05);  // centre of voxel (10, 20, 30)
    const PsCarveStats st = carver.apply(0.0, 2.0, sensor, map);  // echo at x = 3.05: voxel 30
    EXPECT_EQ(st.rays, 1);
    EXPECT_EQ(st.voxels_carved, 20);  // voxels 10..29
    EXPECT_EQ(st.endpoints_in_map, 1);

    const float dlf = static_cast<float>(std::log(0.2 / 0.8));
    float previous = -1e9f;
    for (int ix = 10; ix < 30; ++ix) {
        const std::size_t v = map.linear({ix, 20, 30});
        const float l = map.logOdds(v);
        EXPECT_LT(l, 0.0f) << "voxel " << ix << " not carved";
        EXPECT_GT(l, previous) << "carving must fade toward the echo (Eq. 13)";
        previous = l;
        EXPECT_TRUE(map.psObserved(v));
    }
    // First voxel: the ray runs from 1.05 to 1.10, middle 1.075 -> t = 0.0125.
    EXPECT_NEAR(map.logOdds(map.linear({10, 20, 30})), dlf * std::exp(-0.5 * 0.0125), 1e-5);
    // Voxel 20 spans 2.0..2.1 -> t = (2.05 - 1.05) / 2 = 0.5.
    EXPECT_NEAR(map.logOdds(map.linear({20, 20, 30})), dlf * std::exp(-0.5 * 0.5), 1e-5);
    // The echo's voxel is observed but not carved; nothing beyond it changes.
    EXPECT_FLOAT_EQ(map.logOdds(map.linear({30, 20, 30})), 0.0f);
    EXPECT_TRUE(map.psObserved(map.linear({30, 20, 30})));
    EXPECT_FLOAT_EQ(map.logOdds(map.linear({31, 20, 30})), 0.0f);
    EXPECT_FLOAT_EQ(map.logOdds(map.linear({9, 20, 30})), 0.0f);
    int touched = 0;
    for (std::size_t i = 0; i < map.size(); ++i) touched += map.logOdds(i) != 0.0f;
    EXPECT_EQ(touched, 20);
}

TEST(PsCarving, EndPointHitsByDefaultButNotInThePaperVariant) {
    VoxelMap map = test::originMap();
    PsModel model{singleRay()};
    UpdateConfig cfg;  // fused: the echo is positive evidence of a surface
    EXPECT_TRUE(cfg.ps_endpoint_hits);
    MapperConfig paper;
    applyVariant(Variant::Paper, paper);
    EXPECT_FALSE(paper.update.ps_endpoint_hits);
    PsCarver carver(model, cfg);
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.translation() = Eigen::Vector3d(1.05, 2.05, 3.05);
    carver.apply(0.0, 2.0, sensor, map);
    EXPECT_NEAR(map.logOdds(map.linear({30, 20, 30})), std::log(0.7 / 0.3), 1e-6);
}

TEST(PsCarving, CountsEchoesInTheEndVoxelOnly) {
    VoxelMap map = test::originMap();
    PsModel model{singleRay()};
    PsCarver carver(model, UpdateConfig{});
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.translation() = Eigen::Vector3d(1.05, 2.05, 3.05);
    for (int ping = 0; ping < 3; ++ping) carver.apply(0.0, 2.0, sensor, map);
    EXPECT_EQ(map.psEchoCount(map.linear({30, 20, 30})), 3);  // the echo's voxel, once per ray
    for (int ix = 10; ix < 30; ++ix) EXPECT_EQ(map.psEchoCount(map.linear({ix, 20, 30})), 0) << "crossed voxel " << ix;
    // A voxel crossed far more often than the FLS frame rate never becomes an echo.
    EXPECT_TRUE(map.psObserved(map.linear({20, 20, 30})));
}

// Carving stops at the first bin that could be an echo (UpdateConfig::
// ps_carve_noise_sigmas): nothing from there to the selected echo is carved,
// Eq. 13's weights along the carved part are those of the full ray, and the
// echo stays where it was selected.
TEST(PsCarving, ACarveRangeShortOfTheEchoLeavesTheRestOfTheRayAlone) {
    VoxelMap full = test::originMap(), stopped = test::originMap();
    PsModel model{singleRay()};
    PsCarver carver(model, UpdateConfig{});
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.translation() = Eigen::Vector3d(1.05, 2.05, 3.05);  // centre of voxel (10, 20, 30)
    (void)carver.apply(0.0, 2.0, sensor, full);
    const PsCarveStats st = carver.apply(0.0, 2.0, sensor, stopped, 1.0, 1.5);  // carving stops at x = 2.55: voxel 25
    EXPECT_EQ(st.voxels_carved, 15);  // voxels 10..24
    for (int ix = 10; ix < 25; ++ix) {
        const std::size_t v = stopped.linear({ix, 20, 30});
        EXPECT_FLOAT_EQ(stopped.logOdds(v), full.logOdds(v)) << "voxel " << ix << ": Eq. 13's weight changed";
    }
    for (int ix = 25; ix < 30; ++ix) {
        EXPECT_FLOAT_EQ(stopped.logOdds(stopped.linear({ix, 20, 30})), 0.0f) << "voxel " << ix << " carved past the stop";
        EXPECT_LT(full.logOdds(full.linear({ix, 20, 30})), 0.0f);
    }
    const std::size_t echo = stopped.linear({30, 20, 30});
    EXPECT_EQ(stopped.psEchoCount(echo), 1);
    EXPECT_FLOAT_EQ(stopped.logOdds(echo), full.logOdds(echo));
}

TEST(PsCarving, NoiseRuleIsOnInFusedAndOffInThePaperVariant) {
    MapperConfig fused, paper;
    applyVariant(Variant::Fused, fused);
    applyVariant(Variant::Paper, paper);
    EXPECT_GT(fused.update.ps_carve_noise_sigmas, 0.0);
    EXPECT_GT(fused.update.fls_free_space_noise_sigmas, 0.0);
    EXPECT_EQ(paper.update.ps_carve_noise_sigmas, 0.0);
    EXPECT_EQ(paper.update.fls_free_space_noise_sigmas, 0.0);
}

// UpdateConfig::ps_carve_spare_echo_share: a voxel the PS saw as surface (echoes
// in at least 30 % of the rays that reached it, at least 2 of them) is not
// carved by a later ray passing through it to a farther echo, the way a ramp
// seen from the front is crossed at grazing incidence from behind; once the
// crossings outnumber the echoes by more than 7 to 3, the ray carves it again.
TEST(PsCarving, SparesAVoxelThePsSawAsSurfaceUntilTheCrossingsOutweighIt) {
    PsModel model{singleRay()};
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.translation() = Eigen::Vector3d(1.05, 2.05, 3.05);  // centre of voxel (10, 20, 30)
    const std::size_t surface = test::originMap().linear({20, 20, 30});  // x 2.0..2.1: the range-1.0 echo's voxel
    auto run = [&](const UpdateConfig& cfg, VoxelMap& map, int crossings) {
        const PsCarver carver(model, cfg);
        for (int ping = 0; ping < 2; ++ping) (void)carver.apply(0.0, 1.0, sensor, map);  // two echoes at x = 2.05
        PsCarveStats last;
        for (int ping = 0; ping < crossings; ++ping) last = carver.apply(0.0, 2.0, sensor, map);  // on through it to x = 3.05
        return last;
    };
    UpdateConfig cfg;
    cfg.ps_endpoint_hits = false;  // the log-odds change only by carving
    EXPECT_DOUBLE_EQ(cfg.ps_carve_spare_echo_share, 0.3);
    EXPECT_EQ(cfg.ps_carve_spare_min_echoes, 2);

    VoxelMap spared = test::originMap();
    const PsCarveStats st = run(cfg, spared, 4);  // 2 echoes, 0..3 earlier crossings: 0.7 x 2 >= 0.3 x 3
    EXPECT_EQ(spared.psEchoCount(surface), 2);
    EXPECT_EQ(spared.psCrossings(surface), 4);
    EXPECT_FLOAT_EQ(spared.logOdds(surface), 0.0f) << "the voxel holding the echoes was carved";
    EXPECT_EQ(st.voxels_spared, 1);
    EXPECT_EQ(st.voxels_carved, 20);  // voxels 10..29 visited, the surface spared
    EXPECT_LT(spared.logOdds(spared.linear({19, 20, 30})), 0.0f);  // water in front of it carved as before
    EXPECT_LT(spared.logOdds(spared.linear({21, 20, 30})), 0.0f);  // and behind it

    VoxelMap outweighed = test::originMap();  // spared while 0.7 x 2 >= 0.3 x (crossings so far): the 6th carves
    (void)run(cfg, outweighed, 6);
    const float dlf = static_cast<float>(std::log(0.2 / 0.8));
    EXPECT_NEAR(outweighed.logOdds(surface), dlf * std::exp(-0.5 * 0.5), 1e-5);  // carved once, t = 0.5 (Eq. 13)

    cfg.ps_carve_spare_echo_share = 0.0;  // the paper: every crossed voxel is carved
    VoxelMap carved = test::originMap();
    (void)run(cfg, carved, 4);
    EXPECT_LT(carved.logOdds(surface), 0.0f);

    MapperConfig paper;
    applyVariant(Variant::Paper, paper);
    EXPECT_EQ(paper.update.ps_carve_spare_echo_share, 0.0);

    cfg.ps_carve_spare_echo_share = 0.3;  // one echo is not enough
    VoxelMap single = test::originMap();
    const PsCarver carver(model, cfg);
    (void)carver.apply(0.0, 1.0, sensor, single);
    (void)carver.apply(0.0, 2.0, sensor, single);
    EXPECT_LT(single.logOdds(surface), 0.0f);
}
