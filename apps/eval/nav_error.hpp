// How far the navigation the map was made from (NAV) was from the truth
// (NAV_TRUTH, published by sf-sim when the scenario has NAV errors or motion):
// docs/evaluation.md, "Navigation error". Plain data, no LCM: the log is read
// in nav_log.hpp.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sonarfusion::eval {

struct NavSample {
    int64_t utime = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // NED, m
    double roll = 0, pitch = 0, yaw = 0;                 // rad
};

struct NavErrorStats {
    int64_t samples = 0;            // NAV samples with a NAV_TRUTH sample of the same utime
    int64_t nav_unmatched = 0;      // NAV samples without one
    int64_t truth_unmatched = 0;    // NAV_TRUTH samples without a NAV sample
    double position_rms_m = 0, position_max_m = 0;      // |NAV - truth| in 3-D
    double horizontal_rms_m = 0, horizontal_max_m = 0;  // north-east part
    double depth_rms_m = 0;                             // NED z
    double heading_rms_deg = 0, heading_max_deg = 0;    // yaw difference wrapped to [-180, 180]
    double attitude_rms_deg = 0;                        // roll and pitch differences pooled
};

// NAV against NAV_TRUTH, each NAV sample matched with the truth sample of the
// same utime (either list in any order; a repeated utime keeps its first
// sample). Empty (nullopt) when no sample matches.
[[nodiscard]] std::optional<NavErrorStats> compareNavigation(std::vector<NavSample> nav,
                                                             std::vector<NavSample> truth);

// What sf-eval reports under "navigation": not asked (no --log: no key),
// asked but the log holds no matching NAV_TRUTH (null), or the statistics.
struct NavigationReport {
    bool asked = false;
    std::optional<NavErrorStats> stats;
};

// One line for the console ("navigation: ... ").
[[nodiscard]] std::string navigationSummary(const NavigationReport& report);

}  // namespace sonarfusion::eval
