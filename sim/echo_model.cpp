#include "echo_model.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace sonarfusion::sim {

RangeBinner::RangeBinner(const std::vector<double>& range_of_bin) : range_of_bin_(range_of_bin) {
    if (range_of_bin_.size() < 2) throw std::invalid_argument("RangeBinner: need at least two bins");
    bin_of_sorted_.resize(range_of_bin_.size());
    std::iota(bin_of_sorted_.begin(), bin_of_sorted_.end(), 0);
    std::sort(bin_of_sorted_.begin(), bin_of_sorted_.end(),
              [&](int a, int b) { return range_of_bin_[a] < range_of_bin_[b]; });
    for (int b : bin_of_sorted_) sorted_.push_back(range_of_bin_[b]);
    const std::size_t n = sorted_.size();
    lo_ = std::max(0.0, sorted_[0] - 0.5 * (sorted_[1] - sorted_[0]));
    hi_ = sorted_[n - 1] + 0.5 * (sorted_[n - 1] - sorted_[n - 2]);
}

int RangeBinner::binOf(double range) const {
    if (!(range >= lo_ && range <= hi_)) return -1;
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), range);
    std::size_t i = static_cast<std::size_t>(it - sorted_.begin());
    if (i == sorted_.size()) i = sorted_.size() - 1;
    else if (i > 0 && range - sorted_[i - 1] < sorted_[i] - range) i = i - 1;
    return bin_of_sorted_[i];
}

void accumulateHits(const Scene& scene, const RayHit* hits, int n, const RangeBinner& bins,
                    const ReceiverChain& chain, double* energy) {
    for (int i = 0; i < n; ++i) {
        const RayHit& h = hits[i];
        if (!h.hit) continue;
        const int bin = bins.binOf(h.range);
        if (bin < 0) continue;
        const double r2 = static_cast<double>(h.range) * h.range;
        const double c = h.cos_incidence;
        energy[bin] += scene.reflectionCoefficient(h.mesh) * chain.source_level / (r2 * r2) * c * c;
    }
}

void energyToCounts(const double* energy, const RangeBinner& bins, const ReceiverChain& chain,
                    const NoiseSpec& noise, Rng& rng, uint8_t* out, std::ptrdiff_t stride) {
    for (int b = 0; b < bins.size(); ++b) {
        const double tvg = std::pow(bins.rangeOf(b), chain.tvg_exponent);
        const double amplitude = energy[b] * chain.ray_weight * tvg * chain.gain;
        out[b * stride] = noisyCount(amplitude, noise, rng);
    }
}

}  // namespace sonarfusion::sim
