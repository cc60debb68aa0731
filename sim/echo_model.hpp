// Paper Eq. 15 and the receiver chain shared by the FLS and the PS:
// per hit I = k * (Z - Z0)/(Z + Z0) * I0 / R^4 * cos^2(alpha), summed into the
// nearest range bin; then time-varied gain and a fixed gain give the mean
// amplitude in counts, to which speckle and noise are added (speckle.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "scene.hpp"
#include "speckle.hpp"

namespace sonarfusion::sim {

// Nearest-bin lookup in a range table (any order, any spacing). Ranges more
// than half a bin outside the table are dropped: returns past the maximum
// range never wrap around.
class RangeBinner {
public:
    explicit RangeBinner(const std::vector<double>& range_of_bin);
    // Bin index, or -1 when the range falls outside the table.
    [[nodiscard]] int binOf(double range) const;
    [[nodiscard]] double rangeOf(int bin) const { return range_of_bin_[bin]; }
    [[nodiscard]] int size() const { return static_cast<int>(range_of_bin_.size()); }
    [[nodiscard]] double minRange() const { return lo_; }
    [[nodiscard]] double maxRange() const { return hi_; }

private:
    std::vector<double> range_of_bin_;
    std::vector<double> sorted_;  // ascending
    std::vector<int> bin_of_sorted_;
    double lo_ = 0.0, hi_ = 0.0;  // accepted range interval
};

struct ReceiverChain {
    double source_level = 1.0;   // I0 (k is folded into the gain)
    double tvg_exponent = 4.0;   // amplitude *= R^exponent (40 log R -> 4)
    double gain = 1.0;           // linear, counts per unit of TVG-corrected intensity
    double ray_weight = 1.0;     // bins / rays: makes the level independent of ray count
};

// Adds the Eq. 15 intensity of every hit to its bin of `energy`.
void accumulateHits(const Scene& scene, const RayHit* hits, int n, const RangeBinner& bins,
                    const ReceiverChain& chain, double* energy);

// Turns one channel's binned energy into 8-bit counts written every `stride`
// bytes from `out` (bin order of the binner).
void energyToCounts(const double* energy, const RangeBinner& bins, const ReceiverChain& chain,
                    const NoiseSpec& noise, Rng& rng, uint8_t* out, std::ptrdiff_t stride);

}  // namespace sonarfusion::sim
