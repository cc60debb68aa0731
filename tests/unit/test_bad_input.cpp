#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>

#include <limits>

#include "sonarfusion/mapper.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {
int64_t reason(const Mapper& m, Outcome o) { return m.counters().by_outcome[static_cast<int>(o)]; }

std::vector<float> snapshot(const Mapper& m) { return m.map().logOddsData(); }

Mapper anchoredMapper() {
    Mapper m{MapperConfig{}};
    m.initialiseMapAt(Eigen::Vector3d(3.0, 0.0, 20.0));
    m.addNav(test::trackPose(1000, 0.0));
    m.addNav(test::trackPose(2000, 0.0));
    return m;
}
}  // namespace

TEST(BadInput, NonFinitePosesAreRejectedAndCounted) {
    Mapper m{MapperConfig{}};
    const double bad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                          -std::numeric_limits<double>::infinity()};
    int64_t t = 1;
    for (double b : bad) {
        TimedPose p = test::poseAt(t++, 0, 0, 0);
        p.pose.position.y() = b;
        EXPECT_EQ(m.addNav(p), Outcome::NavNonFinite);
        p = test::poseAt(t++, 0, 0, 0);
        p.pose.yaw = b;
        EXPECT_EQ(m.addNav(p), Outcome::NavNonFinite);
    }
    EXPECT_EQ(reason(m, Outcome::NavNonFinite), 6);
    EXPECT_EQ(m.counters().nav_used, 0);
}

TEST(BadInput, ImagesWhoseSizeDisagreesAreRejected) {
    Mapper m = anchoredMapper();
    const auto before = snapshot(m);
    std::vector<uint8_t> pixels(512 * 96, 255);
    FlsFrame f{1500, 512, 95, pixels.data(), pixels.size()};  // wrong beam count
    EXPECT_EQ(m.addFls(f), Outcome::FlsSizeMismatch);
    f = FlsFrame{1500, 512, 96, pixels.data(), pixels.size() - 96};  // buffer too short
    EXPECT_EQ(m.addFls(f), Outcome::FlsSizeMismatch);
    f = FlsFrame{1500, 512, 96, nullptr, 0};
    EXPECT_EQ(m.addFls(f), Outcome::FlsSizeMismatch);
    f = FlsFrame{1500, -512, -96, pixels.data(), pixels.size()};
    EXPECT_EQ(m.addFls(f), Outcome::FlsSizeMismatch);
    EXPECT_EQ(reason(m, Outcome::FlsSizeMismatch), 4);
    EXPECT_EQ(snapshot(m), before);
}

TEST(BadInput, EmptyAndMalformedPingsAreRejected) {
    Mapper m = anchoredMapper();
    const auto before = snapshot(m);
    auto p = test::blankPing(500, 10.0, 1500, 0.0);
    PsPing empty = p.view;
    empty.bins = 0;
    EXPECT_EQ(m.addPs(empty), Outcome::PsEmpty);
    PsPing null_data = p.view;
    null_data.intensity = nullptr;
    EXPECT_EQ(m.addPs(null_data), Outcome::PsEmpty);
    PsPing bad = p.view;
    bad.head_angle = std::numeric_limits<double>::infinity();
    EXPECT_EQ(m.addPs(bad), Outcome::PsBadGeometry);
    bad = p.view;
    bad.range_max = std::nan("");
    EXPECT_EQ(m.addPs(bad), Outcome::PsBadGeometry);
    EXPECT_EQ(m.addPs(p.view), Outcome::PsNoEcho);  // all zeros: nothing to carve to
    EXPECT_EQ(snapshot(m), before);
}

TEST(BadInput, MessagesWithoutABracketingPoseAreRejected) {
    Mapper m = anchoredMapper();
    auto p = test::blankPing(500, 10.0, 5000, 0.0);  // after the newest NAV: no extrapolation
    p.bins[240] = 255;
    EXPECT_EQ(m.addPs(p.view), Outcome::NoPose);
    EXPECT_EQ(m.addNav(test::trackPose(1500, 0.0)), Outcome::NavOutOfOrder);
    EXPECT_EQ(m.addNav(test::trackPose(2000, 0.0)), Outcome::NavOutOfOrder);  // repeated
    // A 10 s NAV dropout: the samples after it form a new timeline once three
    // agree; the ping inside the gap has nothing to interpolate between.
    for (int i = 0; i < 3; ++i) m.addNav(test::trackPose(2000 + 10000000 + i * 20000, 0.0));
    EXPECT_EQ(m.counters().nav_timeline_resets, 1);
    EXPECT_EQ(m.addPs(p.view), Outcome::NoPose);
    EXPECT_EQ(reason(m, Outcome::NavTimeJump), 0);  // held, then used
    EXPECT_EQ(m.counters().nav_used, 5);
}

namespace {
// NAV every 20 ms along x at 1 m/s from t0 (us), n samples, starting at x0.
void navRun(Mapper& m, int64_t t0, int n, double x0) {
    for (int i = 0; i < n; ++i) m.addNav(test::trackPose(t0 + i * 20000, x0 + 0.02 * i));
}
}  // namespace

// Issue 10, finding 3: one NAV stamped INT64_MAX (or ten years ahead) made every
// later NAV out of order and every sonar message unplaceable.
TEST(BadInput, OneNavStampedFarAheadIsAGlitchNotTheNewTimeline) {
    for (int64_t glitch : {std::numeric_limits<int64_t>::max(), int64_t{1000000} + int64_t{315360000} * 1000000}) {
        Mapper m{MapperConfig{}};
        navRun(m, 1000000, 50, 0.0);
        EXPECT_EQ(m.addNav(test::trackPose(glitch, 5.0)), Outcome::NavTimeJump);
        EXPECT_TRUE(m.navTimelinePending());
        EXPECT_EQ(m.addNav(test::trackPose(1000000 + 50 * 20000, 1.0)), Outcome::Used);
        EXPECT_FALSE(m.navTimelinePending());
        navRun(m, 1000000 + 51 * 20000, 50, 1.02);
        EXPECT_EQ(reason(m, Outcome::NavOutOfOrder), 0);
        EXPECT_EQ(reason(m, Outcome::NavTimeJump), 1);
        EXPECT_EQ(m.counters().nav_timeline_resets, 0);
        const auto pose = m.navPoseAt(1000000 + 75 * 20000 + 10000);
        ASSERT_TRUE(pose);
        EXPECT_NEAR(pose->position.x(), 1.51, 1e-9);
        EXPECT_EQ(*m.newestNavUtime(), 1000000 + 100 * 20000);
    }
}

// Issue 10, finding 4: after a clock step back, sonar was interpolated against
// the stale NAV of the old timeline still in the buffer.
TEST(BadInput, AClockStepBackStartsANewTimelineAndNeverMixesTheOld) {
    Mapper m{MapperConfig{}};
    navRun(m, 100000000, 100, 0.0);  // t = 100..102 s, x = 0..2 m
    // The clock steps back 60 s; the vehicle is now 50 m on.
    EXPECT_EQ(m.addNav(test::trackPose(41000000, 50.0)), Outcome::NavTimeJump);
    EXPECT_EQ(m.addNav(test::trackPose(41020000, 50.02)), Outcome::NavTimeJump);
    EXPECT_FALSE(m.navWouldReset(test::trackPose(41020000, 50.02)));
    EXPECT_TRUE(m.navWouldReset(test::trackPose(41040000, 50.04)));
    EXPECT_EQ(m.addNav(test::trackPose(41040000, 50.04)), Outcome::Used);
    EXPECT_EQ(m.counters().nav_timeline_resets, 1);
    navRun(m, 41060000, 10, 50.06);
    const auto pose = m.navPoseAt(41050000);
    ASSERT_TRUE(pose);
    EXPECT_NEAR(pose->position.x(), 50.05, 1e-9);
    // Nothing of the old timeline is left to interpolate against.
    EXPECT_FALSE(m.navPoseAt(100500000));
    EXPECT_EQ(reason(m, Outcome::NavTimeJump), 0);
    EXPECT_EQ(m.counters().nav_used, 113);
}

TEST(BadInput, HeldNavThatDoesNotContinueItselfRestartsTheCandidate) {
    MapperConfig cfg;
    cfg.nav_timeline_confirm = 2;
    Mapper m{cfg};
    navRun(m, 1000000, 10, 0.0);
    EXPECT_EQ(m.addNav(test::trackPose(900000000, 1.0)), Outcome::NavTimeJump);
    EXPECT_EQ(m.addNav(test::trackPose(500000000, 1.0)), Outcome::NavTimeJump);  // not continuous with it
    EXPECT_EQ(m.navCandidateCount(), 1);
    EXPECT_EQ(m.addNav(test::trackPose(500020000, 1.0)), Outcome::Used);  // confirms the second
    EXPECT_EQ(*m.newestNavUtime(), 500020000);
    EXPECT_EQ(reason(m, Outcome::NavTimeJump), 1);
}

TEST(BadInput, PointsOutsideTheMapAreSkippedNeverWrittenOutside) {
    Mapper m{MapperConfig{}};
    m.initialiseMapAt(Eigen::Vector3d(0.0, 0.0, 20.0));
    // The vehicle just south of the grid (x < -5 m), looking south, away from
    // it: every FLS point and PS ray misses the grid. (From much farther away
    // the map is out of both sonars' reach and not updated at all.)
    TimedPose far = test::poseAt(1000, -5.5, 0.0, 16.88, M_PI);
    m.addNav(far);
    auto frame = test::blankFrame(m.config().fls, 1000);
    std::fill(frame.pixels.begin(), frame.pixels.end(), 255);
    EXPECT_EQ(m.addFls(frame.view), Outcome::Used);
    // Every candidate point of every pixel: per row, the arc samples that keep
    // them a voxel apart, max(N_v, ceil(r * 14 deg / 0.1 m) + 1).
    int64_t points = 0;
    for (int row = 0; row < 512; ++row) {
        const double r = 0.83 + (511.0 - row) / 511.0 * 9.17;
        points += std::max(5, static_cast<int>(std::ceil(r * 14.0 * M_PI / 180.0 / 0.1)) + 1);
    }
    EXPECT_EQ(m.counters().fls_points_outside_map, 96 * points);
    auto p = test::blankPing(500, 10.0, 1000, 0.0);
    p.bins[400] = 255;
    EXPECT_EQ(m.addPs(p.view), Outcome::Used);
    EXPECT_EQ(m.counters().ps_endpoints_outside_map, 21);
    for (float l : m.map().logOddsData()) ASSERT_EQ(l, 0.0f);
}

TEST(BadInput, ImpossibleConfigIsAClearError) {
    MapperConfig c;
    c.update.p_free = 0.6;  // would make carving add occupancy
    try {
        Mapper m(c);
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("p_free"), std::string::npos);
    }
}

TEST(BadInput, TheIssue9RulesRefuseImpossibleSettings) {
    auto refused = [](const MapperConfig& c, const char* key) {
        const std::string err = validateConfig(c);
        return !err.empty() && err.find(key) != std::string::npos;
    };
    MapperConfig c;
    EXPECT_TRUE(validateConfig(c).empty());
    c.update.fls_arc_spacing_voxels = 1e-6;  // would size a table of millions of samples per beam
    EXPECT_TRUE(refused(c, "fls_arc_spacing_voxels"));
    c = MapperConfig{};
    c.segmentation.ps_echo_min_fraction = 1.5;
    EXPECT_TRUE(refused(c, "ps_echo_min_fraction"));
    c = MapperConfig{};
    c.segmentation.ps_echo_min_count = 0;
    EXPECT_TRUE(refused(c, "ps_echo_min_count"));
    c = MapperConfig{};
    c.segmentation.fls_only_extension = 1000;  // steps are counted in a byte per voxel
    EXPECT_TRUE(refused(c, "fls_only_extension"));
}
