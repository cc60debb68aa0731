// Robust statistics on a scratch buffer, shared by the seabed fits (the
// detector's plane, the segmenter's height field): the median, and the
// standard deviation of normal data estimated from the median absolute
// deviation. Both reorder the buffer in place (std::nth_element); nothing is
// allocated.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace sonarfusion {

// Normal data: sigma = kMadToSigma x median absolute deviation.
inline constexpr double kMadToSigma = 1.4826;

// The upper median (element n / 2 in order) of the first n values; reorders them.
[[nodiscard]] inline double medianInPlace(std::vector<double>& values, std::size_t n) {
    const auto begin = values.begin(), mid = begin + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(begin, mid, begin + static_cast<std::ptrdiff_t>(n));
    return *mid;
}

// kMadToSigma x the median of the first n values' absolute deviations from
// `centre` (their median, or a fitted model's zero); overwrites them.
[[nodiscard]] inline double robustSigmaInPlace(std::vector<double>& values, std::size_t n, double centre) {
    for (std::size_t i = 0; i < n; ++i) values[i] = std::abs(values[i] - centre);
    return kMadToSigma * medianInPlace(values, n);
}

}  // namespace sonarfusion
