// Deterministic noise: a counter-based seed per (scenario seed, channel,
// sequence, beam; random.hpp), so the same seed gives the same bytes whatever
// the thread count, and speckle (random-phase scatterers per pixel) plus a water noise
// floor turn a mean echo amplitude into an 8-bit count.
#pragma once

#include <cmath>
#include <cstdint>

#include "random.hpp"  // Rng, noiseSeed, NoiseChannel
#include "scenario.hpp"

namespace sonarfusion::sim {

// Paper Eq. 16: the pixel is a complex sum of a coherent part and N scatterers
// with random phase, plus complex Gaussian water noise of rms `floor`; the
// count is its modulus sqrt(Re^2 + Im^2), rounded and clipped to 0..255.
// E[count^2] = mean_amplitude^2 + floor^2.
[[nodiscard]] uint8_t noisyCount(double mean_amplitude, const NoiseSpec& noise, Rng& rng);

}  // namespace sonarfusion::sim
