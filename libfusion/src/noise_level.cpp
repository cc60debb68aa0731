#include "sonarfusion/noise_level.hpp"

#include <algorithm>
#include <cstdlib>

namespace sonarfusion {

namespace {
int lowerMedian(const IntensityHistogram& h, std::size_t samples) {
    std::size_t seen = 0;
    for (int v = 0; v < 256; ++v) {
        seen += h[static_cast<std::size_t>(v)];
        if (2 * seen >= samples) return v;
    }
    return 255;
}
}  // namespace

double noiseLevelOf(const IntensityHistogram& hist, std::size_t samples, double sigmas) {
    if (samples == 0) return 255.0;
    const int median = lowerMedian(hist, samples);
    IntensityHistogram deviation{};
    for (int v = 0; v < 256; ++v)
        deviation[static_cast<std::size_t>(std::abs(v - median))] += hist[static_cast<std::size_t>(v)];
    return median + sigmas * 1.4826 * std::max(1, lowerMedian(deviation, samples));
}

}  // namespace sonarfusion
