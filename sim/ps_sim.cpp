#include "ps_sim.hpp"

#include <cmath>

#include "sonarfusion/beam_direction.hpp"

namespace sonarfusion::sim {

namespace {
std::vector<double> binRanges(const PsGeometry& g) {
    std::vector<double> r(g.bins);
    for (int b = 0; b < g.bins; ++b) r[b] = g.range_min + b * (g.range_max - g.range_min) / (g.bins - 1);
    return r;
}

// n cell-centred samples over [lo, hi].
std::vector<double> spread(double lo, double hi, int n) {
    std::vector<double> out(n);
    for (int i = 0; i < n; ++i) out[i] = lo + (i + 0.5) / n * (hi - lo);
    return out;
}
}  // namespace

PsSimulator::PsSimulator(const Scene& scene, const Scenario& s)
    : scene_(scene),
      geometry_(s.ps),
      mount_(s.ps_mount),
      noise_(s.noise),
      seed_(s.seed),
      binner_(binRanges(s.ps)),
      fan_(spread(s.ps.fan_min, s.ps.fan_max, s.ps_sim.rays_fan)),
      vertical_(spread(-0.5 * s.ps_sim.beam_width_vertical, 0.5 * s.ps_sim.beam_width_vertical,
                       s.ps_sim.rays_vertical)) {
    chain_.source_level = s.ps_sim.source_level;
    chain_.tvg_exponent = s.ps_sim.tvg_db_per_decade / 10.0;
    chain_.gain = std::pow(10.0, (kPsBaseGainDb + s.ps_sim.gain_db) / 20.0);
    chain_.ray_weight = static_cast<double>(s.ps.bins) / raysPerPing();
}

std::vector<uint8_t> PsSimulator::ping(const Pose& vehicle, double head_angle, int64_t sequence) const {
    const Eigen::Isometry3d world_from_sensor = sensorToWorld(vehicle, mount_);
    const Eigen::Matrix3f rotation = world_from_sensor.linear().cast<float>();
    std::vector<Eigen::Vector3f> dirs;
    dirs.reserve(raysPerPing());
    for (double v : vertical_) {
        const double down = geometry_.tilt + head_angle + v;  // Eq. 11 depression
        for (double theta : fan_) dirs.push_back(rotation * beamDirection(down, theta).cast<float>());
    }
    std::vector<RayHit> hits(dirs.size());
    scene_.cast(world_from_sensor.translation().cast<float>(), dirs.data(), static_cast<int>(dirs.size()), 0.0f,
                static_cast<float>(binner_.maxRange()), hits.data());

    std::vector<double> energy(binner_.size(), 0.0);
    accumulateHits(scene_, hits.data(), static_cast<int>(hits.size()), binner_, chain_, energy.data());
    std::vector<uint8_t> out(binner_.size());
    Rng rng(noiseSeed(seed_, NoiseChannel::Ps, sequence, 0));
    energyToCounts(energy.data(), binner_, chain_, noise_, rng, out.data(), 1);
    return out;
}

}  // namespace sonarfusion::sim
