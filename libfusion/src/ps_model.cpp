#include "sonarfusion/ps_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sonarfusion/beam_direction.hpp"
#include "sonarfusion/noise_level.hpp"

namespace sonarfusion {

PsPingError validatePing(const PsPing& ping) {
    if (ping.bins <= 0 || ping.intensity == nullptr) return PsPingError::Empty;
    if (ping.bins < 2 || !std::isfinite(ping.head_angle) || !std::isfinite(ping.range_min) ||
        !std::isfinite(ping.range_max) || ping.range_min < 0.0 || ping.range_max <= ping.range_min ||
        std::fabs(ping.head_angle) > M_PI)
        return PsPingError::BadGeometry;
    return PsPingError::None;
}

namespace {
double normaliser(const PsPing& ping, const PsSelectionConfig& cfg, int& peak) {
    peak = 0;
    for (int i = 0; i < ping.bins; ++i)
        if (ping.intensity[i] > peak) peak = ping.intensity[i];
    return cfg.normalise_by_ping_max ? static_cast<double>(peak) : 255.0;
}

int firstUsableBin(const PsPing& ping, const PsSelectionConfig& cfg) {
    int b = 0;
    while (b < ping.bins && rangeOfBin(ping, b) < cfg.min_range) ++b;
    return b;
}
}  // namespace

std::optional<int> selectClosestGroup(const PsPing& ping, const PsSelectionConfig& cfg) {
    const std::optional<PsEchoGroup> g = closestGroup(ping, cfg);
    if (!g) return std::nullopt;
    return g->peak;
}

std::optional<PsEchoGroup> closestGroup(const PsPing& ping, const PsSelectionConfig& cfg) {
    if (validatePing(ping) != PsPingError::None) return std::nullopt;
    int peak = 0;
    const double norm = normaliser(ping, cfg, peak);
    if (peak < cfg.min_peak_intensity || norm <= 0.0) return std::nullopt;
    // Bins are already sorted by range, so the first bin above tau starts the
    // nearest group; the group ends at the first bin that falls back below.
    // With weak_echoes_group, a bin as strong as the weakest echo a ping may
    // have at all (min_peak_intensity) belongs to a group too, whatever tau
    // says: a surface in part of the fan returns less than the seabed across
    // all of it, and is still the nearest surface.
    double threshold = cfg.group_threshold;
    if (cfg.weak_echoes_group) threshold = std::min(threshold, cfg.min_peak_intensity / norm);
    int b = firstUsableBin(ping, cfg);
    while (b < ping.bins && ping.intensity[b] / norm <= threshold) ++b;
    if (b == ping.bins) return std::nullopt;
    PsEchoGroup g{b, b};
    for (; b < ping.bins && ping.intensity[b] / norm > threshold; ++b)
        if (ping.intensity[b] > ping.intensity[g.peak]) g.peak = b;
    return g;
}

int firstEchoBin(const PsPing& ping, const PsSelectionConfig& cfg, double sigmas, int window_bins) {
    if (validatePing(ping) != PsPingError::None) return -1;
    const int b0 = firstUsableBin(ping, cfg);
    if (ping.bins - b0 < 2) return -1;
    IntensityHistogram hist{};
    for (int b = b0; b < ping.bins; ++b) ++hist[ping.intensity[b]];
    const std::size_t samples = static_cast<std::size_t>(ping.bins - b0);
    const double level = noiseLevelOf(hist, samples, sigmas);
    // The window's sum must exceed w (median + sigmas * sigma / sqrt(w)): the
    // mean of w independent noise bins scatters sqrt(w) times less than one
    // bin. Speckle is correlated over a few bins, so noise alone stops about
    // one ping in ten early (docs/algorithm.md, "Weak echoes at the fan's edge").
    const int w = window_bins >= 2 ? window_bins : 0;
    double window_need = 0.0;
    if (w > 0) {
        const double median = noiseLevelOf(hist, samples, 0.0);  // the level at 0 sigmas
        window_need = w * median + std::sqrt(static_cast<double>(w)) * (level - median);
    }
    int window_sum = 0;
    for (int b = b0; b < ping.bins; ++b) {
        if (b + 1 < ping.bins && ping.intensity[b] > level && ping.intensity[b + 1] > level) return b;
        if (w == 0) continue;
        window_sum += ping.intensity[b];
        if (b - b0 >= w) window_sum -= ping.intensity[b - w];
        if (b - b0 + 1 >= w && window_sum > window_need) return b - w + 1;
    }
    return -1;
}

std::optional<int> maxIntensityBin(const PsPing& ping, const PsSelectionConfig& cfg) {
    if (validatePing(ping) != PsPingError::None) return std::nullopt;
    int best = -1, best_val = -1;
    for (int b = firstUsableBin(ping, cfg); b < ping.bins; ++b) {
        if (ping.intensity[b] > best_val) {
            best_val = ping.intensity[b];
            best = b;
        }
    }
    if (best < 0 || best_val < cfg.min_peak_intensity) return std::nullopt;
    return best;
}

PsModel::PsModel(const PsGeometry& g) : g_(g), nh_(g.fan_samples) {
    if (nh_ < 1 || nh_ > 1024) throw std::invalid_argument("PS geometry: fan_samples must be in 1..1024");
    if (!std::isfinite(g.fan_min) || !std::isfinite(g.fan_max) || g.fan_max < g.fan_min)
        throw std::invalid_argument("PS geometry: need fan_min <= fan_max");
    if (!std::isfinite(g.tilt)) throw std::invalid_argument("PS geometry: tilt must be finite");
    if (!(g.range_max > g.range_min) || g.range_min < 0.0)
        throw std::invalid_argument("PS geometry: need 0 <= range_min < range_max");
    fan_.resize(nh_);
    for (int k = 0; k < nh_; ++k)
        fan_[k] = nh_ == 1 ? 0.5 * (g.fan_min + g.fan_max) : g.fan_min + k * (g.fan_max - g.fan_min) / (nh_ - 1);
}

Eigen::Vector3d PsModel::direction(double head_angle, int k) const {
    return beamDirection(g_.tilt + head_angle, fan_[k]);  // Eq. 11: phi_t2 + phi_p, theta_k
}

Eigen::Vector3d PsModel::centreDirection(double head_angle) const { return beamDirection(g_.tilt + head_angle, 0.0); }

}  // namespace sonarfusion
