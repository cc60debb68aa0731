// Profiling sonar: range selection (paper 2.3) and candidate points (Eqs. 10-11).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

// A borrowed view of one PS ping: intensity per range bin at one head angle.
struct PsPing {
    int64_t utime = 0;
    double head_angle = 0.0;  // phi_p, rad
    double range_min = 0.0;   // m, range of bin 0
    double range_max = 0.0;   // m, range of the last bin
    int bins = 0;
    const uint8_t* intensity = nullptr;
};

// Why a ping cannot be used; None when it can.
enum class PsPingError { None, Empty, BadGeometry };
[[nodiscard]] PsPingError validatePing(const PsPing& ping);

[[nodiscard]] inline double rangeOfBin(const PsPing& p, int bin) {
    return p.bins < 2 ? p.range_min : p.range_min + bin * (p.range_max - p.range_min) / (p.bins - 1);
}

// Paper 2.3, closest-group rule: normalise to 0..1, keep bins above tau, split
// them into runs of consecutive bins, take the nearest run, and within it the
// bin of highest intensity. Returns that bin, or nothing (no update).
[[nodiscard]] std::optional<int> selectClosestGroup(const PsPing& ping, const PsSelectionConfig& cfg);

// The nearest group itself: its first bin (where the nearest surface begins)
// and its strongest bin (the selected echo).
struct PsEchoGroup {
    int first = 0;
    int peak = 0;
};
[[nodiscard]] std::optional<PsEchoGroup> closestGroup(const PsPing& ping, const PsSelectionConfig& cfg);

// The nearest bin (beyond cfg.min_range) that could be an echo: it and the next
// one stand `sigmas` robust standard deviations (1.4826 x MAD) above the
// ping's median, which is its noise (most bins of a ping are water); or, with
// window_bins >= 2, the first of window_bins consecutive bins whose mean
// stands sigmas / sqrt(window_bins) robust standard deviations above it (an
// echo too weak per bin, as long as the window: a surface in a few rays of
// the fan). -1: none.
[[nodiscard]] int firstEchoBin(const PsPing& ping, const PsSelectionConfig& cfg, double sigmas, int window_bins = 0);

// Paper 2.1: the plain maximum-intensity bin (object detection uses this).
[[nodiscard]] std::optional<int> maxIntensityBin(const PsPing& ping, const PsSelectionConfig& cfg);

class PsModel {
public:
    explicit PsModel(const PsGeometry& g);  // throws std::invalid_argument on bad geometry

    [[nodiscard]] int fanSamples() const { return nh_; }
    // Eq. 10.
    [[nodiscard]] double fanAngle(int k) const { return fan_[k]; }
    // Eq. 11 without the range: unit direction of fan sample k at head angle phi_p.
    [[nodiscard]] Eigen::Vector3d direction(double head_angle, int k) const;
    // Unit direction of the fan's centre line (theta = 0) at head angle phi_p.
    [[nodiscard]] Eigen::Vector3d centreDirection(double head_angle) const;
    [[nodiscard]] const PsGeometry& geometry() const { return g_; }

private:
    PsGeometry g_;
    int nh_;
    std::vector<double> fan_;  // theta_k (Eq. 10)
};

}  // namespace sonarfusion
