// Deterministic noise: a counter-based seed per (scenario seed, channel,
// sequence, beam), so the same seed gives the same bytes whatever the thread
// count, and speckle (random-phase scatterers per pixel) plus a water noise
// floor turn a mean echo amplitude into an 8-bit count.
#pragma once

#include <cmath>
#include <cstdint>

#include "scenario.hpp"

namespace sonarfusion::sim {

enum class NoiseChannel : uint32_t { Fls = 1, Ps = 2 };

// SplitMix64: tiny, fast, and identical on every platform (unlike std::
// distributions, whose output is implementation-defined).
class Rng {
public:
    explicit Rng(uint64_t seed) : state_(seed) {}
    uint64_t next() {
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1).
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    // Standard normal (Box-Muller, one value per call).
    double gaussian() {
        const double u1 = 1.0 - uniform();  // (0, 1]
        const double u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }

private:
    uint64_t state_;
};

[[nodiscard]] uint64_t noiseSeed(uint64_t seed, NoiseChannel channel, int64_t sequence, uint32_t beam);

// Paper Eq. 16: the pixel is a complex sum of a coherent part and N scatterers
// with random phase, plus complex Gaussian water noise of rms `floor`; the
// count is its modulus sqrt(Re^2 + Im^2), rounded and clipped to 0..255.
// E[count^2] = mean_amplitude^2 + floor^2.
[[nodiscard]] uint8_t noisyCount(double mean_amplitude, const NoiseSpec& noise, Rng& rng);

}  // namespace sonarfusion::sim
