// Deterministic random numbers shared by the speckle (sf_sim) and the
// navigation and motion models (sf_scenario): a counter-based seed per
// (scenario seed, stream, sequence, index), so the same seed gives the same
// numbers whatever the thread count, and each stream is independent of the
// others (turning NAV noise on does not change the speckle).
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>

namespace sonarfusion::sim {

// Independent streams. Fls and Ps are the speckle of the two sonars, Nav the
// NAV errors (docs/navigation.md), Motion the phases of the vehicle motion.
enum class NoiseChannel : uint32_t { Fls = 1, Ps = 2, Nav = 3, Motion = 4 };

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

[[nodiscard]] inline uint64_t noiseSeed(uint64_t seed, NoiseChannel channel, int64_t sequence, uint32_t beam) {
    // Mix each part through SplitMix so nearby inputs give unrelated streams.
    Rng mix(seed);
    uint64_t h = mix.next();
    for (uint64_t part : {static_cast<uint64_t>(channel), static_cast<uint64_t>(sequence), static_cast<uint64_t>(beam)}) {
        Rng r(h ^ (part * 0xD1B54A32D192ED03ull));
        h = r.next();
    }
    return h;
}

}  // namespace sonarfusion::sim
