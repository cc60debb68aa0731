#include "nav_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sonarfusion::eval {

namespace {
void sortUnique(std::vector<NavSample>& v) {
    std::stable_sort(v.begin(), v.end(), [](const NavSample& a, const NavSample& b) { return a.utime < b.utime; });
    v.erase(std::unique(v.begin(), v.end(), [](const NavSample& a, const NavSample& b) { return a.utime == b.utime; }),
            v.end());
}
constexpr double kRadToDeg = 180.0 / M_PI;
}  // namespace

std::optional<NavErrorStats> compareNavigation(std::vector<NavSample> nav, std::vector<NavSample> truth) {
    sortUnique(nav);
    sortUnique(truth);
    NavErrorStats s;
    double sum_position = 0, sum_horizontal = 0, sum_depth = 0, sum_heading = 0, sum_attitude = 0;
    std::size_t j = 0;
    for (const NavSample& n : nav) {
        while (j < truth.size() && truth[j].utime < n.utime) {
            ++s.truth_unmatched;
            ++j;
        }
        if (j == truth.size() || truth[j].utime != n.utime) {
            ++s.nav_unmatched;
            continue;
        }
        const NavSample& t = truth[j++];
        const Eigen::Vector3d d = n.position - t.position;
        const double horizontal = d.head<2>().norm();
        const double heading = std::fabs(std::remainder(n.yaw - t.yaw, 2.0 * M_PI)) * kRadToDeg;
        const double roll = std::remainder(n.roll - t.roll, 2.0 * M_PI) * kRadToDeg;
        const double pitch = std::remainder(n.pitch - t.pitch, 2.0 * M_PI) * kRadToDeg;
        ++s.samples;
        sum_position += d.squaredNorm();
        sum_horizontal += horizontal * horizontal;
        sum_depth += d.z() * d.z();
        sum_heading += heading * heading;
        sum_attitude += 0.5 * (roll * roll + pitch * pitch);
        s.position_max_m = std::max(s.position_max_m, d.norm());
        s.horizontal_max_m = std::max(s.horizontal_max_m, horizontal);
        s.heading_max_deg = std::max(s.heading_max_deg, heading);
    }
    s.truth_unmatched += static_cast<int64_t>(truth.size() - j);
    if (s.samples == 0) return std::nullopt;
    const double n = static_cast<double>(s.samples);
    s.position_rms_m = std::sqrt(sum_position / n);
    s.horizontal_rms_m = std::sqrt(sum_horizontal / n);
    s.depth_rms_m = std::sqrt(sum_depth / n);
    s.heading_rms_deg = std::sqrt(sum_heading / n);
    s.attitude_rms_deg = std::sqrt(sum_attitude / n);
    return s;
}

std::string navigationSummary(const NavigationReport& report) {
    if (!report.asked) return "";
    if (!report.stats) return "navigation: no NAV_TRUTH in the log matches its NAV (error unknown)";
    const NavErrorStats& s = *report.stats;
    char line[320];
    std::snprintf(line, sizeof line,
                  "navigation (NAV vs NAV_TRUTH, %lld samples): position rms %.3f m, max %.3f m "
                  "(horizontal rms %.3f m, depth rms %.3f m); heading rms %.2f deg, max %.2f deg; "
                  "roll/pitch rms %.2f deg",
                  static_cast<long long>(s.samples), s.position_rms_m, s.position_max_m, s.horizontal_rms_m,
                  s.depth_rms_m, s.heading_rms_deg, s.heading_max_deg, s.attitude_rms_deg);
    return line;
}

}  // namespace sonarfusion::eval
