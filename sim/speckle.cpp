#include "speckle.hpp"

#include <algorithm>

namespace sonarfusion::sim {

uint8_t noisyCount(double mean_amplitude, const NoiseSpec& noise, Rng& rng) {
    double re = mean_amplitude, im = 0.0;
    if (noise.speckle && mean_amplitude > 0.0) {
        const double coherent = std::sqrt(noise.coherent_fraction);
        const double per_scatterer = std::sqrt((1.0 - noise.coherent_fraction) / noise.scatterers);
        double sum_re = 0.0, sum_im = 0.0;
        for (int k = 0; k < noise.scatterers; ++k) {
            const double phase = 2.0 * M_PI * rng.uniform();
            sum_re += std::cos(phase);
            sum_im += std::sin(phase);
        }
        re = mean_amplitude * (coherent + per_scatterer * sum_re);
        im = mean_amplitude * per_scatterer * sum_im;
    }
    if (noise.floor > 0.0) {
        re += noise.floor * M_SQRT1_2 * rng.gaussian();
        im += noise.floor * M_SQRT1_2 * rng.gaussian();
    }
    const double count = std::sqrt(re * re + im * im);
    return static_cast<uint8_t>(std::clamp(std::lround(count), 0L, 255L));
}

}  // namespace sonarfusion::sim
