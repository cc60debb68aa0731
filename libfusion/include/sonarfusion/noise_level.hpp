// The level above which a sonar sample is an echo rather than noise, from a
// histogram of the samples' intensities: their lower median plus `sigmas`
// robust standard deviations (1.4826 x the median absolute deviation, at least
// one count, so a constant image still has a level above itself). Most of a
// sonar image or ping is water or shadow, so the median and MAD are the
// noise's (docs/algorithm.md, "Carving stops at the first echo").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace sonarfusion {

using IntensityHistogram = std::array<uint32_t, 256>;

// `samples` is the histogram's total count; 255 when it is 0.
[[nodiscard]] double noiseLevelOf(const IntensityHistogram& hist, std::size_t samples, double sigmas);

}  // namespace sonarfusion
