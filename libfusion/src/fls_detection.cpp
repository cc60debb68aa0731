#include "sonarfusion/fls_detection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sonarfusion {

std::optional<Eigen::Vector3d> flsReturnNearerThanSeabed(const FlsFrame& frame, const FlsModel& model,
                                                         const Eigen::Isometry3d& world_from_sensor,
                                                         const SeabedFit& seabed, int vote_threshold, double margin) {
    const Eigen::Vector3d sensor = world_from_sensor.translation();
    const double depth_below = seabed.depthAt(sensor.head<2>()) - sensor.z() - margin;
    if (!(depth_below > 0.0)) return std::nullopt;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int col = 0; col < frame.cols; ++col) {
        // A ray meets the raised plane at depth_below / closing rate; the arc's
        // nearest such range is on one of its edges (the rate is monotonic in
        // elevation) or, with roll, near its centre.
        double nearest = std::numeric_limits<double>::infinity();
        for (int e = 0; e < 3; ++e) {  // lower edge, centre, upper edge
            const double rate = seabed.closingRate(world_from_sensor.linear() * model.edgeDirection(col, e).cast<double>());
            if (rate > 1e-6) nearest = std::min(nearest, depth_below / rate);
        }
        const Eigen::Vector3d centre = world_from_sensor.linear() * model.edgeDirection(col, 1).cast<double>();
        // Rows run from the far end: walk in from the nearest row while it is nearer than the seabed.
        for (int row = frame.rows - 1; row >= 0; --row) {
            const double r = model.rangeOfRow(row);
            if (!(r < nearest)) break;
            if (frame.data[static_cast<std::size_t>(row) * frame.cols + col] <= vote_threshold) continue;
            sum += sensor + r * centre;
            ++n;
        }
    }
    if (n == 0) return std::nullopt;
    return sum / n;
}

namespace {
// The seabed band is cut into this many equal parts of each beam's band: the
// seabed's returns weaken with range (grazing incidence falls across the band,
// more so on a seabed falling away), so dark pixels grow likelier toward the
// far end, and a chain fitted to the whole band would call the far end's
// ordinary runs rare.
constexpr int kBandParts = 8;

struct BeamBand {
    double near = 0.0, far = 0.0;  // m
    [[nodiscard]] int part(double r) const {
        return std::clamp(static_cast<int>((r - near) / (far - near) * kBandParts), 0, kBandParts - 1);
    }
};
}  // namespace

std::optional<Eigen::Vector3d> flsShadowOnSeabed(const FlsFrame& frame, const FlsModel& model,
                                                 const Eigen::Isometry3d& world_from_sensor, const SeabedFit& seabed,
                                                 double margin, int noise_level, double false_alarm,
                                                 bool like_water) {
    const Eigen::Vector3d sensor = world_from_sensor.translation();
    const double depth_below = seabed.depthAt(sensor.head<2>()) - sensor.z();
    if (!(depth_below - margin > 0.0) || !(false_alarm > 0.0)) return std::nullopt;
    const double lo = model.elevationMin(), hi = model.elevationMax();
    const auto rate = [&](int col, double e) {
        return seabed.closingRate(world_from_sensor.linear() * model.directionAt(col, e).cast<double>());
    };
    const auto edge_rate = [&](int col, int e) {  // at the lower edge, centre, upper edge
        return seabed.closingRate(world_from_sensor.linear() * model.edgeDirection(col, e).cast<double>());
    };
    // A beam's fastest- and slowest-closing rays (the rate is monotonic in
    // elevation, so an edge, or with roll near the centre).
    struct Closing {
        double fastest = 0.0, slowest = std::numeric_limits<double>::infinity();
    };
    const auto closing_of = [&](int col) {
        Closing c;
        for (int e = 0; e < 3; ++e) {
            const double v = edge_rate(col, e);
            c.fastest = std::max(c.fastest, v);
            c.slowest = std::min(c.slowest, v);
        }
        return c;
    };
    // The band where the arc surely meets the plane: from where its
    // fastest-closing ray meets the plane lowered by the margin to where its
    // slowest meets it raised; a ray that never closes leaves no far end.
    const auto band_of = [&](const Closing& c) -> std::optional<BeamBand> {
        if (!(c.slowest > 1e-6)) return std::nullopt;
        const BeamBand b{(depth_below + margin) / c.fastest, (depth_below - margin) / c.slowest};
        if (!(b.far > b.near)) return std::nullopt;
        return b;
    };
    const auto value_at = [&](int row, int col) { return frame.data[static_cast<std::size_t>(row) * frame.cols + col]; };
    const auto dark_at = [&](int row, int col) { return value_at(row, col) <= noise_level; };
    // Where a walk out from the nearest row may start for a band beginning at
    // `near`: with ranges falling with the row, the last row at least that far
    // (the rows nearer only skip); otherwise the nearest row.
    const auto band_start = [&](double near) {
        return model.rangesFallWithRow() ? model.lastRowAtLeast(near) : frame.rows - 1;
    };
    // Pass 1: per part of the band, how often a pixel is dark and how often
    // one after a dark pixel is dark too. Rows run from the far end: walk out
    // from the nearest row.
    std::array<long, kBandParts> pixels{}, dark{}, after_dark{}, dark_after_dark{};
    long band_pixels = 0, band_dark = 0;
    double band_dark_sum = 0.0;
    // like_water: the dark pixels of the water column, nearer than the
    // seabed could return on any ray of their beam (the fastest-closing ray
    // meeting the plane raised by the margin), hold the receiver's noise
    // alone. Objects in the water return bright there and are not counted.
    long water_dark = 0;
    double water_sum = 0.0;
    for (int col = 0; col < frame.cols; ++col) {
        const Closing closing = closing_of(col);
        if (like_water && closing.fastest > 1e-6) {
            const double seabed_earliest = (depth_below - margin) / closing.fastest;
            for (int row = frame.rows - 1; row >= 0 && model.rangeOfRow(row) < seabed_earliest; --row) {
                if (!dark_at(row, col)) continue;
                water_sum += value_at(row, col);
                ++water_dark;
            }
        }
        const std::optional<BeamBand> band = band_of(closing);
        if (!band) continue;
        bool previous_dark = false, started = false;
        for (int row = band_start(band->near); row >= 0; --row) {
            const double r = model.rangeOfRow(row);
            if (r < band->near) continue;
            if (r > band->far) break;
            const int k = band->part(r);
            const bool d = dark_at(row, col);
            ++pixels[k];
            dark[k] += d;
            if (d) {
                band_dark_sum += value_at(row, col);
                ++band_dark;
            }
            if (started && previous_dark) {
                ++after_dark[k];
                dark_after_dark[k] += d;
            }
            started = true;
            previous_dark = d;
            ++band_pixels;
        }
    }
    std::array<double, kBandParts> log_p{}, log_q{};
    for (int k = 0; k < kBandParts; ++k) {
        // A run's pixels are counted in their parts, so every log taken in
        // pass 2 is of a non-zero share; a part where every dark pixel follows
        // another makes a run there no rarer (log 1 = 0).
        log_p[k] = pixels[k] > 0 ? std::log(static_cast<double>(dark[k]) / pixels[k]) : 0.0;
        log_q[k] = after_dark[k] > 0 ? std::log(static_cast<double>(dark_after_dark[k]) / after_dark[k]) : 0.0;
    }
    // Pass 2: every dark run that starts after a seabed return (the run ends
    // at the next return or at the band's far end), scored by the chance of
    // its rows under the chain of the parts they lie in; over the frame's N
    // possible starts that bounds the expected count of runs as rare (the
    // frame's false alarms, whatever part they fall in).
    const double log_n = std::log(static_cast<double>(std::max<long>(1, band_pixels)));
    // like_water: a shadow returns nothing, so its pixels are the water
    // column's noise; a seabed turned away from the sonar (the lee of a
    // swell, a slope falling away) still returns weakly and its dark runs are
    // brighter. A run is a shadow only when its mean lies nearer the water's
    // dark pixels' mean than the band's dark pixels' mean: no level to choose,
    // both measured on this frame.
    const bool judge_level = like_water && water_dark > 0 && band_dark > 0;
    const double shadow_level =
        judge_level ? 0.5 * (water_sum / static_cast<double>(water_dark) + band_dark_sum / static_cast<double>(band_dark))
                    : 0.0;
    double best_log = std::log(false_alarm);
    int best_col = -1;
    double best_range = 0.0;
    for (int col = 0; col < frame.cols; ++col) {
        const std::optional<BeamBand> band = band_of(closing_of(col));
        if (!band) continue;
        bool bright_before = false;
        double run_log = 0.0, run_start = 0.0, run_sum = 0.0;
        int run = 0;
        const auto judge = [&] {
            if (run > 0 && bright_before && log_n + run_log < best_log &&
                (!judge_level || run_sum < shadow_level * run)) {
                best_log = log_n + run_log;
                best_col = col;
                best_range = run_start;
            }
        };
        for (int row = band_start(band->near); row >= 0; --row) {
            const double r = model.rangeOfRow(row);
            if (r < band->near) continue;
            if (r > band->far) break;
            const int k = band->part(r);
            if (dark_at(row, col)) {
                run_log += run == 0 ? log_p[k] : log_q[k];
                run_sum += value_at(row, col);
                if (run == 0) run_start = r;
                ++run;
                continue;
            }
            judge();
            run = 0;
            run_log = run_sum = 0.0;
            bright_before = true;
        }
        judge();  // a run into the band's far end: the shadow of an object near it
    }
    if (best_col < 0) return std::nullopt;
    // The elevation whose ray meets the plane at the run's first range: the
    // closing rate there is depth / range; bisect (the rate is monotonic).
    const double wanted = depth_below / best_range;
    double a = lo, b = hi;
    const bool rising = edge_rate(best_col, 2) > edge_rate(best_col, 0);
    for (int k = 0; k < 30; ++k) {
        const double m = 0.5 * (a + b);
        if ((rate(best_col, m) < wanted) == rising) a = m;
        else b = m;
    }
    const Eigen::Vector3d d = world_from_sensor.linear() * model.directionAt(best_col, 0.5 * (a + b)).cast<double>();
    return sensor + best_range * d;
}

}  // namespace sonarfusion
