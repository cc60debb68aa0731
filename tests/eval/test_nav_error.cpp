// sf-eval's navigation report: NAV against NAV_TRUTH matched by utime, and the
// "navigation" key of report.json (absent without --log, null without truth).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "nav_error.hpp"
#include "report.hpp"

namespace sonarfusion::eval {
namespace {

NavSample sample(int64_t utime, double x, double y, double z, double yaw_deg, double roll_deg = 0) {
    NavSample s;
    s.utime = utime;
    s.position = Eigen::Vector3d(x, y, z);
    s.yaw = yaw_deg * M_PI / 180.0;
    s.roll = roll_deg * M_PI / 180.0;
    return s;
}

TEST(NavError, MatchesByUtimeAndMeasuresPositionAndHeading) {
    // Truth at 0..3; NAV at 1..4 (out of order, 4 has no truth, 0 has no NAV).
    const std::vector<NavSample> truth = {sample(0, 0, 0, 10, 0), sample(1, 1, 0, 10, 179),
                                          sample(2, 2, 0, 10, 90), sample(3, 3, 0, 10, 0)};
    const std::vector<NavSample> nav = {sample(3, 3, 0.4, 10, 0), sample(1, 1.3, 0, 10.4, -179, 2),
                                        sample(2, 2, 0, 10, 90), sample(4, 9, 9, 9, 0)};
    const auto s = compareNavigation(nav, truth);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->samples, 3);
    EXPECT_EQ(s->nav_unmatched, 1);
    EXPECT_EQ(s->truth_unmatched, 1);
    // Errors: 0.5 m (0.3 north, 0.4 down), 0, 0.4 m (east).
    EXPECT_NEAR(s->position_rms_m, std::sqrt((0.25 + 0.16) / 3), 1e-12);
    EXPECT_NEAR(s->position_max_m, 0.5, 1e-12);
    EXPECT_NEAR(s->horizontal_rms_m, std::sqrt((0.09 + 0.16) / 3), 1e-12);
    EXPECT_NEAR(s->horizontal_max_m, 0.4, 1e-12);
    EXPECT_NEAR(s->depth_rms_m, std::sqrt(0.16 / 3), 1e-12);
    // -179 vs 179 degrees is 2 degrees, across the wrap.
    EXPECT_NEAR(s->heading_max_deg, 2.0, 1e-9);
    EXPECT_NEAR(s->heading_rms_deg, std::sqrt(4.0 / 3), 1e-9);
    EXPECT_NEAR(s->attitude_rms_deg, std::sqrt(0.5 * 4.0 / 3), 1e-9);
}

TEST(NavError, NothingMatchedIsUnknown) {
    EXPECT_FALSE(compareNavigation({sample(1, 0, 0, 0, 0)}, {}));
    EXPECT_FALSE(compareNavigation({sample(1, 0, 0, 0, 0)}, {sample(2, 0, 0, 0, 0)}));
    EXPECT_FALSE(compareNavigation({}, {}));
}

TEST(NavError, ReportKeyAbsentNullOrObject) {
    VariantScore v;
    v.variant = "fused";
    EXPECT_FALSE(nlohmann::json::parse(reportJson("x", {v})).contains("navigation"));
    NavigationReport asked;
    asked.asked = true;
    const auto null_nav = nlohmann::json::parse(reportJson("x", {v}, "", asked));
    ASSERT_TRUE(null_nav.contains("navigation"));
    EXPECT_TRUE(null_nav["navigation"].is_null());
    asked.stats = compareNavigation({sample(1, 0.3, 0.4, 0, 1)}, {sample(1, 0, 0, 0, 0)});
    const auto j = nlohmann::json::parse(reportJson("x", {v}, "", asked))["navigation"];
    for (const char* key : {"position_rms_m", "position_max_m", "heading_rms_deg", "heading_max_deg", "samples"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_NEAR(j["position_rms_m"].get<double>(), 0.5, 1e-12);
    EXPECT_NEAR(j["heading_max_deg"].get<double>(), 1.0, 1e-9);
    EXPECT_EQ(j["samples"], 1);
    EXPECT_NE(navigationSummary(asked).find("1 samples"), std::string::npos);
    EXPECT_EQ(navigationSummary(NavigationReport{}), "");
}

}  // namespace
}  // namespace sonarfusion::eval
