#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <set>
#include <string>

#include "sonarfusion/fls_update.hpp"
#include "sonarfusion/variant.hpp"
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
        // Eq. 6 to the letter: N_v samples per arc, no free space (each has its own tests).
        cfg.fls_arc_spacing_voxels = 0.0;
        cfg.fls_free_space = false;
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

// Water (8) everywhere but seabed speckle from 5.40 to 7.2 m (rows 160..260):
// one pixel in eight at 210, the rest at 160; and a 6 x 6 patch of 255 at
// 5.8 m (rows 232..237, beams 45..50). A flat seabed 4 m below the sensor
// could first return at 5.40 m.
test::OwnedFrame speckleWithPatch(const FlsGeometry& g) {
    auto frame = test::blankFrame(g, 0);
    for (int row = 0; row < g.rows; ++row)
        for (int col = 0; col < g.beams; ++col)
            test::setPixel(frame, row, col, row < 160 || row > 260 ? 8 : (row * 7 + col * 3) % 8 == 0 ? 210 : 160);
    for (int row = 232; row < 238; ++row)
        for (int col = 45; col < 51; ++col) test::setPixel(frame, row, col, 255);
    return frame;
}

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

// --- Arc sampling that follows the voxel size (UpdateConfig::fls_arc_spacing_voxels)
TEST(FlsUpdate, ArcSamplesFollowTheVoxelSizeSoTheArcIsUnbroken) {
    Fixture fx;
    fx.cfg.fls_arc_spacing_voxels = 1.0;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    const int row = 100, col = 48;  // about 8.0 m: the paper's 5 samples lie 0.49 m apart
    test::setPixel(frame, row, col, 204);
    const FlsUpdateStats st = up.apply(frame.view, fx.sensor, fx.map);
    const double r = 0.83 + (511.0 - row) / 511.0 * 9.17;
    EXPECT_EQ(up.arcSamples(r), static_cast<int>(std::ceil(r * 14.0 * kDeg / 0.1)) + 1);
    EXPECT_EQ(st.points_in_map, up.arcSamples(r));
    // The voxels hit form one 26-connected chain from the top of the arc to its bottom.
    std::vector<VoxelIndex> hit;
    for (std::size_t i = 0; i < fx.map.size(); ++i)
        if (fx.map.logOdds(i) > 0.0f) hit.push_back(fx.map.fromLinear(i));
    EXPECT_GE(static_cast<int>(hit.size()), 15);
    // Connected: a flood fill over 26-neighbours from the first voxel reaches all.
    std::vector<bool> reached(hit.size(), false);
    std::vector<std::size_t> todo{0};
    reached[0] = true;
    while (!todo.empty()) {
        const VoxelIndex a = hit[todo.back()];
        todo.pop_back();
        for (std::size_t j = 0; j < hit.size(); ++j)
            if (!reached[j] && std::max({std::abs(hit[j].x - a.x), std::abs(hit[j].y - a.y), std::abs(hit[j].z - a.z)}) <= 1) {
                reached[j] = true;
                todo.push_back(j);
            }
    }
    EXPECT_EQ(std::count(reached.begin(), reached.end(), true), static_cast<long>(hit.size())) << "the arc has a gap";
}

// --- The FLS's own free space (UpdateConfig::fls_free_space)
TEST(FlsUpdate, WaterBeforeTheFirstReturnIsCarvedAndTheReturnIsNot) {
    Fixture fx;
    fx.cfg.fls_free_space = true;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    auto frame = test::blankFrame(fx.geom, 0);
    const int row = 200, col = 60;  // first (and only) return of beam 60 at ~6.4 m
    test::setPixel(frame, row, col, 204);
    const FlsUpdateStats st = up.apply(frame.view, fx.sensor, fx.map);
    EXPECT_GT(st.voxels_freed, 0);
    const double r_first = 0.83 + (511.0 - row) / 511.0 * 9.17;
    const float hit = static_cast<float>(std::log(0.7 / 0.3) * 0.3 * 204.0 / 255.0);
    const float freed = static_cast<float>(-3.0 * std::log(0.7 / 0.3) * 0.3);  // three full-intensity votes
    EXPECT_FLOAT_EQ(up.freeIncrement(), freed);
    int n_hit = 0, n_freed = 0;
    for (std::size_t i = 0; i < fx.map.size(); ++i) {
        const float l = fx.map.logOdds(i);
        if (l == 0.0f) continue;
        if (l > 0.0f) {
            EXPECT_NEAR(l, hit, 1e-6) << "a voxel the return hit is never freed in the same frame";
            ++n_hit;
        } else {
            EXPECT_NEAR(l, freed, 1e-6) << "each voxel freed once per frame";
            ++n_freed;
        }
    }
    // Beam 60's own water: points of its arcs short of the return are freed,
    // and behind the return nothing of that beam is (other beams, which saw
    // no return at all, free their whole range).
    for (double r = 1.0; r < r_first - 0.2; r += 0.5) {
        VoxelIndex v;
        ASSERT_TRUE(fx.map.worldToIndex(r * fx.model.directionAt(col, 0.0).cast<double>(), v));
        EXPECT_NEAR(fx.map.logOdds(fx.map.linear(v)), freed, 1e-6) << "beam water at " << r << " m not freed";
    }
    EXPECT_EQ(n_hit, st.voxels_updated);
    EXPECT_EQ(n_freed, st.voxels_freed);
    // Beams with no return at all free their whole range (inside the map), so
    // far more voxels are freed than the one beam's water alone.
    EXPECT_GT(n_freed, 1000);
}

// A frame that saw a voxel as water outweighs several frames that voted it
// (UpdateConfig::fls_free_vote_ratio). A vote only says that one voxel of its
// elevation arc holds a surface; measured against ground truth a surface is
// seen through in 0-5 % of the frames that voted or freed it, water voted
// beside objects in about 56 % (docs/algorithm.md, "FLS free-space weight").
// At the old weight (alpha_F ln(P_f/(1-P_f)), 1.6 votes) a voxel voted in 7
// frames and seen through in 2 ended occupied (+0.95): the mirror of a small
// object across the track was reported that way.
TEST(FlsUpdate, AVoxelSeenThroughTwiceIsNotMadeOccupiedBySevenVotes) {
    Fixture fx;
    fx.cfg.fls_free_space = true;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    const int col = 60, row_near = 200, row_far = 100;  // ~6.4 m and ~8.2 m
    const std::size_t v = fx.expectedVoxel(row_near, col, 2);
    // Returns across every beam (a wall), so no neighbouring beam without a
    // return frees its whole range through the voxels looked at.
    auto voting = test::blankFrame(fx.geom, 0);
    auto seeing_through = test::blankFrame(fx.geom, 0);  // the first returns lie beyond v
    for (int c = 0; c < fx.geom.beams; ++c) {
        test::setPixel(voting, row_near, c, 255);
        test::setPixel(seeing_through, row_far, c, 255);
    }
    for (int i = 0; i < 7; ++i) {
        (void)up.apply(voting.view, fx.sensor, fx.map);
        if (i == 2 || i == 5) (void)up.apply(seeing_through.view, fx.sensor, fx.map);
    }
    const float occupied = static_cast<float>(std::log(0.7 / 0.3));  // segmentation's p > 0.7
    const float vote = static_cast<float>(std::log(0.7 / 0.3) * 0.3);
    EXPECT_NEAR(fx.map.logOdds(v), 7 * vote - 2 * 3 * vote, 1e-4);
    EXPECT_LT(fx.map.logOdds(v), occupied) << "seen as water twice, yet occupied";
    // A voxel of the far return's own arc, voted twice and never seen through, keeps its votes.
    EXPECT_NEAR(fx.map.logOdds(fx.expectedVoxel(row_far, col, 2)), 2 * vote, 1e-4);
}

TEST(FlsUpdate, TheFreeSpaceRuleIsOffInThePaperVariant) {
    MapperConfig paper;
    applyVariant(Variant::Paper, paper);
    EXPECT_FALSE(paper.update.fls_free_space);
    EXPECT_EQ(paper.update.fls_arc_spacing_voxels, 0.0);
    MapperConfig fused;
    applyVariant(Variant::Fused, fused);
    EXPECT_TRUE(fused.update.fls_free_space);
    EXPECT_GT(fused.update.fls_arc_spacing_voxels, 0.0);
}

// A return nearer than the seabed anywhere on its beam's elevation arc cannot
// be the seabed: its voxels are counted as voted above the seabed, once per
// frame (VoxelMap::flsAboveSeabedVotes; docs/algorithm.md, "Off-swath parts").
// A return at a range where the seabed lies on the arc is not, nor is any
// return while no seabed is known. A seabed rising toward the sonar explains
// returns a flat one would not.
TEST(FlsUpdate, VotesNearerThanTheSeabedOnTheirArcAreCountedAboveIt) {
    Fixture fx;
    fx.cfg.fls_once_per_frame = true;
    fx.cfg.fls_free_space = true;
    FlsUpdater up(fx.model, fx.cfg, fx.map);
    // Flat seabed 4 m below the sensor: the steepest ray (47 deg) meets it,
    // raised by the margin (0.05 m: half a voxel, rms 0), at 5.40 m.
    SeabedFit flat;
    flat.depth = 4.0;
    const int col = 48, row_near = 290, row_far = 234;  // 4.80 m and 5.80 m
    auto frame = test::blankFrame(fx.geom, 0);
    test::setPixel(frame, row_near, col, 255);
    test::setPixel(frame, row_far, col, 255);
    (void)up.apply(frame.view, fx.sensor, fx.map);  // no seabed known yet
    const std::size_t near_voxel = fx.expectedVoxel(row_near, col, 2), far_voxel = fx.expectedVoxel(row_far, col, 2);
    EXPECT_EQ(fx.map.flsAboveSeabedVotes(near_voxel), 0) << "counted without a seabed";
    up.setSeabed(flat);
    for (int i = 0; i < 2; ++i) {
        const FlsUpdateStats st = up.apply(frame.view, fx.sensor, fx.map);
        EXPECT_GT(st.voxels_above_seabed, 0);
    }
    for (int k = 0; k < 5; ++k) {
        EXPECT_EQ(fx.map.flsAboveSeabedVotes(fx.expectedVoxel(row_near, col, k)), 2) << "arc sample " << k;
        EXPECT_EQ(fx.map.flsAboveSeabedVotes(fx.expectedVoxel(row_far, col, k)), 0) << "arc sample " << k;
    }
    EXPECT_GT(fx.map.logOdds(far_voxel), 0.0f);  // voted all the same
    // Rising 0.2 m per m ahead, the seabed meets the steepest ray at 4.55 m:
    // the 4.80 m return may now be seabed.
    SeabedFit rising = flat;
    rising.gradient = Eigen::Vector2d(-0.2, 0.0);
    up.setSeabed(rising);
    EXPECT_EQ(up.apply(frame.view, fx.sensor, fx.map).voxels_above_seabed, 0);
    EXPECT_EQ(fx.map.flsAboveSeabedVotes(near_voxel), 2);
}

// A low part of an object beside the PS swath returns from no nearer than the
// seabed could, but as a compact region brighter than the seabed's speckle at
// that range: its votes count as ones the seabed cannot explain
// (UpdateConfig::fls_highlight_above_seabed).
TEST(FlsUpdate, AHighlightBeyondTheSeabedRangeCountsAboveIt) {
    auto votes = [](bool highlights) {
        Fixture fx;
        fx.cfg.fls_once_per_frame = true;
        fx.cfg.fls_highlight_above_seabed = highlights;
        FlsUpdater up(fx.model, fx.cfg, fx.map);
        SeabedFit flat;
        flat.depth = 4.0;  // the seabed could first return at 5.40 m (previous test)
        up.setSeabed(flat);
        const auto frame = speckleWithPatch(fx.geom);
        (void)up.apply(frame.view, fx.sensor, fx.map);
        return std::make_pair(fx.map.flsAboveSeabedVotes(fx.expectedVoxel(234, 48, 2)),
                              fx.map.flsAboveSeabedVotes(fx.expectedVoxel(250, 20, 2)));
    };
    const auto on = votes(true), off = votes(false);
    EXPECT_EQ(on.first, 1) << "the patch";
    EXPECT_EQ(on.second, 0) << "speckle";
    EXPECT_EQ(off.first, 0);
    EXPECT_EQ(off.second, 0);
}

// The judged-later pass (UpdateConfig::fls_seabed_judged_later) asks only for
// the above-seabed counts: applyAboveSeabedVotes must hand the sink the very
// aboveSeabed calls apply() does (the same voxels, as often; the order does
// not matter to a count), in every counting mode, and no log-odds update; it skips the free space and the pixels the seabed
// explains, so it touches fewer voxels.
TEST(FlsUpdate, TheAboveSeabedPassGivesApplysAboveSeabedVotesAndNothingElse) {
    struct Recorder {
        std::vector<std::size_t> above;
        int adds = 0;
        void add(std::size_t, float, uint8_t) { ++adds; }
        void aboveSeabed(std::size_t v) { above.push_back(v); }
    };
    struct Mode {
        bool once_per_frame, free_space, highlights;
    };
    for (const Mode m : {Mode{true, true, true}, Mode{true, false, false}, Mode{false, false, false},
                         Mode{false, true, true}}) {
        Fixture fx;
        fx.cfg.fls_arc_spacing_voxels = 1.0;
        fx.cfg.fls_once_per_frame = m.once_per_frame;
        fx.cfg.fls_free_space = m.free_space;
        fx.cfg.fls_highlight_above_seabed = m.highlights;
        FlsUpdater up(fx.model, fx.cfg, fx.map);
        SeabedFit flat;
        flat.depth = 4.0;
        up.setSeabed(flat);
        // Seabed speckle beyond 5.4 m, a bright patch on it, and returns nearer
        // than the seabed on a few beams (rows 290..300: 4.6-4.8 m).
        auto frame = speckleWithPatch(fx.geom);
        for (int row = 290; row <= 300; ++row)
            for (int col = 10; col < 14; ++col) test::setPixel(frame, row, col, 200);
        Recorder full, only;
        const FlsUpdateStats st_full = up.apply(frame.view, fx.sensor, fx.map, full);
        const FlsUpdateStats st_only = up.applyAboveSeabedVotes(frame.view, fx.sensor, fx.map, only);
        const std::string mode = "once " + std::to_string(m.once_per_frame) + " free " +
                                 std::to_string(m.free_space) + " highlights " + std::to_string(m.highlights);
        ASSERT_FALSE(full.above.empty()) << mode;
        std::sort(full.above.begin(), full.above.end());
        std::sort(only.above.begin(), only.above.end());
        EXPECT_EQ(only.above, full.above) << mode;
        EXPECT_EQ(st_only.voxels_above_seabed, st_full.voxels_above_seabed) << mode;
        EXPECT_EQ(only.adds, 0) << mode;
        EXPECT_EQ(st_only.voxels_updated, 0) << mode;
        EXPECT_EQ(st_only.voxels_freed, 0) << mode;
        EXPECT_GT(full.adds, static_cast<int>(full.above.size())) << mode;
    }
}

// --- Where the free space stops (UpdateConfig::fls_free_space_noise_sigmas)
namespace {
// Noise of median 10 and MAD 2 (6, 8, 10, 12, 14 equally often): at 4 robust
// standard deviations the echo level is ceil(10 + 4 x 1.4826 x 2) = 22.
void fillNoise(test::OwnedFrame& f) {
    for (int row = 0; row < f.view.rows; ++row)
        for (int col = 0; col < f.view.cols; ++col)
            test::setPixel(f, row, col, static_cast<uint8_t>(6 + 2 * ((row * 7 + col * 3) % 5)));
}
}  // namespace

TEST(FlsUpdate, TheImageNoiseLevelIsItsMedianPlusRobustDeviations) {
    Fixture fx;
    auto frame = test::blankFrame(fx.geom, 0);
    fillNoise(frame);
    EXPECT_EQ(noiseLevel(frame.view, 4.0), 22);
    EXPECT_EQ(noiseLevel(frame.view, 0.0), 10);
    auto flat = test::blankFrame(fx.geom, 0);
    for (auto& p : flat.pixels) p = 10;
    EXPECT_EQ(noiseLevel(flat.view, 4.0), 16) << "a constant image: the deviation counts as one";
}

// A surface that returns weakly (above the image's noise, below the vote
// threshold) is not water: the free space stops there. Before this rule it ran
// on to the first pixel above 150 and carved the weak surface (the wedge's and
// the 60 deg box's flanks; docs/algorithm.md, "Carving stops at the first echo").
// A lone noise pixel does not stop it.
TEST(FlsUpdate, TheFreeSpaceStopsAtAWeakEchoAndNotAtALoneNoisePixel) {
    const int row_weak = 300, row_vote = 200, row_spike = 400;  // ~4.6, ~6.4 and ~2.8 m
    auto run = [&](double sigmas) {
        Fixture fx;
        fx.cfg.fls_free_space = true;
        fx.cfg.fls_free_space_noise_sigmas = sigmas;
        FlsUpdater up(fx.model, fx.cfg, fx.map);
        auto frame = test::blankFrame(fx.geom, 0);
        fillNoise(frame);
        for (int c = 0; c < fx.geom.beams; ++c) {  // a wall: no neighbouring beam frees the same voxels
            test::setPixel(frame, row_weak, c, 80);       // two consecutive rows above 22, below 150
            test::setPixel(frame, row_weak - 1, c, 80);
            test::setPixel(frame, row_vote, c, 204);
        }
        test::setPixel(frame, row_spike, 60, 90);  // one pixel only: noise
        (void)up.apply(frame.view, fx.sensor, fx.map);
        const double r_between = 0.83 + (511.0 - 250) / 511.0 * 9.17, r_after_spike = 4.0;
        VoxelIndex between, after_spike;
        EXPECT_TRUE(fx.map.worldToIndex(r_between * fx.model.directionAt(60, 0.0).cast<double>(), between));
        EXPECT_TRUE(fx.map.worldToIndex(r_after_spike * fx.model.directionAt(60, 0.0).cast<double>(), after_spike));
        return std::make_pair(fx.map.logOdds(fx.map.linear(between)), fx.map.logOdds(fx.map.linear(after_spike)));
    };
    const auto [between_noise_rule, after_spike_noise_rule] = run(4.0);
    EXPECT_FLOAT_EQ(between_noise_rule, 0.0f) << "the water behind a weak echo was carved";
    EXPECT_LT(after_spike_noise_rule, 0.0f) << "the lone noise pixel stopped the free space";
    const auto [between_old, after_spike_old] = run(0.0);
    EXPECT_LT(between_old, 0.0f) << "with 0 the free space runs up to the first vote";
    EXPECT_LT(after_spike_old, 0.0f);
}
