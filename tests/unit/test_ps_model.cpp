#include <gtest/gtest.h>

#include <cmath>

#include "sonarfusion/pose.hpp"
#include "sonarfusion/ps_carving.hpp"
#include "sonarfusion/ps_model.hpp"
#include "sonarfusion/variant.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST(PsSelection, BinRangesSpanTheWindow) {
    auto p = test::blankPing(501, 10.0, 0, 0.0);
    EXPECT_DOUBLE_EQ(rangeOfBin(p.view, 0), 0.0);
    EXPECT_DOUBLE_EQ(rangeOfBin(p.view, 500), 10.0);
    EXPECT_DOUBLE_EQ(rangeOfBin(p.view, 250), 5.0);
}

TEST(PsSelection, NearWeakGroupBeatsFarStrongGroup) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    // Near group: bins 100..104, weak but above 0.7 of the peak (0.7 * 255 = 178.5).
    const uint8_t near[] = {185, 190, 200, 195, 186};
    for (int i = 0; i < 5; ++i) p.bins[100 + i] = near[i];
    // Far group: the strongest echo of the ping.
    for (int i = 0; i < 5; ++i) p.bins[300 + i] = 255;
    PsSelectionConfig cfg;
    const auto sel = selectClosestGroup(p.view, cfg);
    ASSERT_TRUE(sel.has_value());
    EXPECT_EQ(*sel, 102);  // the nearest group's own maximum
    // The detector's rule takes the plain maximum instead.
    EXPECT_EQ(*maxIntensityBin(p.view, cfg), 300);
}

namespace {
PsSelectionConfig tauOnly() {  // the paper's rule (section 2.3)
    PsSelectionConfig c;
    c.weak_echoes_group = false;
    return c;
}
}  // namespace

TEST(PsSelection, BelowTauIsNotAGroup) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    p.bins[100] = 170;  // 0.667 of the peak: below tau
    p.bins[300] = 255;
    EXPECT_EQ(*selectClosestGroup(p.view, tauOnly()), 300);
}

TEST(PsSelection, AWeakNearerSurfaceIsTheNearestGroupByDefault) {
    // An object in part of the fan (60 counts) in front of the seabed summed
    // across all of it (200): tau x peak = 140 hides the object, the echo
    // level that makes a ping's peak an echo at all (min_peak_intensity 40)
    // does not; water noise (25) stays below both.
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    for (int b = 0; b < 500; b += 7) p.bins[b] = 25;
    p.bins[180] = 55;
    p.bins[181] = 60;
    p.bins[300] = 200;
    EXPECT_EQ(*selectClosestGroup(p.view, tauOnly()), 300);
    EXPECT_EQ(*selectClosestGroup(p.view, PsSelectionConfig{}), 181);
    MapperConfig paper;
    applyVariant(Variant::Paper, paper);
    EXPECT_FALSE(paper.ps_selection.weak_echoes_group);
}

TEST(PsSelection, GroupsAreSplitAtTheFirstGap) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    p.bins[100] = 200;
    p.bins[101] = 10;   // gap
    p.bins[102] = 255;  // next group, stronger
    EXPECT_EQ(*selectClosestGroup(p.view, PsSelectionConfig{}), 100);
}

TEST(PsSelection, NoEchoMeansNoUpdate) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    for (auto& b : p.bins) b = 12;  // water noise only, below min_peak_intensity
    EXPECT_FALSE(selectClosestGroup(p.view, PsSelectionConfig{}).has_value());
    EXPECT_FALSE(maxIntensityBin(p.view, PsSelectionConfig{}).has_value());
    PsSelectionConfig absolute = tauOnly();
    absolute.normalise_by_ping_max = false;  // tau on I/255
    p.bins[200] = 160;                       // 0.63: below tau on the absolute scale
    EXPECT_FALSE(selectClosestGroup(p.view, absolute).has_value());
    EXPECT_TRUE(selectClosestGroup(p.view, PsSelectionConfig{}).has_value());
}

TEST(PsSelection, IgnoresTransducerRinging) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    p.bins[2] = 255;  // 4 cm: inside min_range
    p.bins[250] = 200;
    EXPECT_EQ(*selectClosestGroup(p.view, PsSelectionConfig{}), 250);
}

TEST(PsModel, FanSamplesAndDirectionsFollowEq10And11) {
    PsModel m{PsGeometry{}};
    ASSERT_EQ(m.fanSamples(), 21);
    EXPECT_NEAR(m.fanAngle(0), -10 * kDeg, 1e-12);
    EXPECT_NEAR(m.fanAngle(10), 0.0, 1e-12);
    EXPECT_NEAR(m.fanAngle(20), 10 * kDeg, 1e-12);
    // Head at +20 deg: 60 deg down in total.
    const Eigen::Vector3d d = m.direction(20 * kDeg, 20);
    EXPECT_NEAR(d.x(), std::cos(60 * kDeg) * std::cos(10 * kDeg), 1e-12);
    EXPECT_NEAR(d.y(), std::cos(60 * kDeg) * std::sin(10 * kDeg), 1e-12);
    EXPECT_NEAR(d.z(), std::sin(60 * kDeg), 1e-12);
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    EXPECT_TRUE(m.centreDirection(-20 * kDeg).isApprox(m.direction(-20 * kDeg, 10)));
}

TEST(PsModel, ValidatesPings) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    EXPECT_EQ(validatePing(p.view), PsPingError::None);
    PsPing empty = p.view;
    empty.bins = 0;
    EXPECT_EQ(validatePing(empty), PsPingError::Empty);
    PsPing bad = p.view;
    bad.head_angle = std::nan("");
    EXPECT_EQ(validatePing(bad), PsPingError::BadGeometry);
    bad = p.view;
    bad.range_max = -1.0;
    EXPECT_EQ(validatePing(bad), PsPingError::BadGeometry);
}

// Issue 11: the profiling direction follows the full NAV attitude (hand-computed).
TEST(PsModel, PitchAndRollMoveTheProfileWhereGeometrySays) {
    PsModel m{PsGeometry{}};
    Pose p;
    p.pitch = -5 * kDeg;  // nose down: head at 0 looks 45 deg down
    Eigen::Vector3d d = sensorToWorld(p, Mounting{}).linear() * m.centreDirection(0.0);
    EXPECT_NEAR(d.x(), std::cos(45 * kDeg), 1e-12);
    EXPECT_NEAR(d.y(), 0.0, 1e-12);
    EXPECT_NEAR(d.z(), std::sin(45 * kDeg), 1e-12);
    Pose r;
    r.roll = -3 * kDeg;  // port down: the belly turns to starboard (+y)
    d = sensorToWorld(r, Mounting{}).linear() * m.centreDirection(10 * kDeg);  // 50 deg down
    EXPECT_NEAR(d.x(), std::cos(50 * kDeg), 1e-12);
    EXPECT_NEAR(d.y(), std::sin(3 * kDeg) * std::sin(50 * kDeg), 1e-12);
    EXPECT_NEAR(d.z(), std::cos(3 * kDeg) * std::sin(50 * kDeg), 1e-12);
}

// Where carving stops (carveStopRange): at the first of two consecutive bins
// above the ping's noise (median + 4 robust standard deviations), when that
// comes before the nearest group, else at the group's first bin. A surface in
// part of the fan returns below the group threshold and is still not water.
TEST(PsSelection, CarvingStopsAtTheFirstBinThatCouldBeAnEcho) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);
    // Noise of median 10 and MAD 2: the echo level at 4 sigmas is 10 + 4 x 1.4826 x 2 = 21.9.
    for (int b = 0; b < 500; ++b) p.bins[b] = static_cast<uint8_t>(6 + 2 * ((b * 3) % 5));
    p.bins[100] = 35;                     // a lone noise spike: not an echo
    p.bins[200] = p.bins[201] = 30;       // weak (below min_peak_intensity 40): not a group
    for (int b = 300; b < 306; ++b) p.bins[b] = 120;
    p.bins[303] = 200;                    // the group's peak, the selected echo
    const PsSelectionConfig cfg;
    const std::optional<PsEchoGroup> g = closestGroup(p.view, cfg);
    ASSERT_TRUE(g.has_value());
    EXPECT_EQ(g->first, 300);
    EXPECT_EQ(g->peak, 303);
    EXPECT_EQ(*selectClosestGroup(p.view, cfg), 303);
    EXPECT_EQ(firstEchoBin(p.view, cfg, 4.0), 200);
    EXPECT_DOUBLE_EQ(carveStopRange(p.view, *g, cfg, 4.0), rangeOfBin(p.view, 200));
    EXPECT_LT(carveStopRange(p.view, *g, cfg, 0.0), 0.0) << "0: carve up to the selected echo";
    // Without the weak bins: the group's first bin.
    p.bins[200] = p.bins[201] = 10;
    EXPECT_DOUBLE_EQ(carveStopRange(p.view, *g, cfg, 4.0), rangeOfBin(p.view, 300));
}

// A surface struck by only a few of the fan's rays (an object at the fan's
// edge) returns in every bin of its range, each below the per-bin level, while
// the seabed struck by all of them forms the nearest group: a run of a voxel's
// length (window) whose mean stands 4 / sqrt(w) robust sigmas above the median
// stops the carving there (UpdateConfig::ps_carve_echo_window_voxels).
TEST(PsSelection, CarvingStopsAtARunOfWeakEchoesAVoxelLong) {
    auto p = test::blankPing(500, 10.0, 0, 0.0);  // 2 cm bins: a 0.1 m voxel is 5 of them
    // Noise cycling 6 12 8 14 10: median 10, MAD 2, per-bin level 21.9; any 5
    // consecutive bins sum to 50, and the window needs more than
    // 5 x 10 + sqrt(5) x 11.9 = 76.5.
    for (int b = 0; b < 500; ++b) p.bins[b] = static_cast<uint8_t>(6 + 2 * ((b * 3) % 5));
    for (int b = 200; b < 210; ++b) p.bins[b] = 16;  // below the per-bin level throughout (mean 16 > 15.3)
    for (int b = 300; b < 306; ++b) p.bins[b] = 120;
    p.bins[303] = 200;
    const PsSelectionConfig cfg;
    const std::optional<PsEchoGroup> g = closestGroup(p.view, cfg);
    ASSERT_TRUE(g.has_value());
    EXPECT_EQ(firstEchoBin(p.view, cfg, 4.0), 300) << "no pair above the per-bin level before the group";
    EXPECT_EQ(firstEchoBin(p.view, cfg, 4.0, 5), 200);
    const double bin = rangeOfBin(p.view, 1) - rangeOfBin(p.view, 0);
    EXPECT_DOUBLE_EQ(carveStopRange(p.view, *g, cfg, 4.0, 5 * bin), rangeOfBin(p.view, 200));
    EXPECT_DOUBLE_EQ(carveStopRange(p.view, *g, cfg, 4.0), rangeOfBin(p.view, 300)) << "no window: the group";
    EXPECT_LT(carveStopRange(p.view, *g, cfg, 0.0, 5 * bin), 0.0) << "0 sigmas: carve up to the selected echo";
    // Too weak for the window (mean 14 < 15.3): the carving runs on to the group.
    for (int b = 200; b < 210; ++b) p.bins[b] = 14;
    EXPECT_EQ(firstEchoBin(p.view, cfg, 4.0, 5), 300);
    EXPECT_DOUBLE_EQ(carveStopRange(p.view, *g, cfg, 4.0, 5 * bin), rangeOfBin(p.view, 300));
}
