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
    m.addNav(test::trackPose(2000 + 10000000, 0.0));  // a 10 s NAV gap
    EXPECT_EQ(m.addPs(p.view), Outcome::NavGapTooLarge);
    EXPECT_EQ(m.addNav(test::trackPose(1500, 0.0)), Outcome::NavOutOfOrder);
}

TEST(BadInput, PointsOutsideTheMapAreSkippedNeverWrittenOutside) {
    Mapper m{MapperConfig{}};
    m.initialiseMapAt(Eigen::Vector3d(0.0, 0.0, 20.0));
    // The vehicle 200 m away: every FLS point and PS ray misses the grid.
    TimedPose far = test::poseAt(1000, 200.0, 0.0, 16.88);
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
