#include "fls_sim.hpp"

#include <cmath>

#include "parallel.hpp"
#include "sonarfusion/beam_direction.hpp"

namespace sonarfusion::sim {

namespace {
std::vector<double> rowRanges(const FlsModel& m) {
    std::vector<double> r(m.rows());
    for (int i = 0; i < m.rows(); ++i) r[i] = m.rangeOfRow(i);
    return r;
}

// Azimuth width of beam c: the spacing to its neighbours (uniform: fov / w).
double beamWidth(const FlsModel& m, int c) {
    if (m.cols() == 1) return 0.0;
    const int lo = c == 0 ? 0 : c - 1, hi = c == m.cols() - 1 ? c : c + 1;
    return std::fabs(m.bearingOfColumn(hi) - m.bearingOfColumn(lo)) / (hi - lo);
}
}  // namespace

FlsSimulator::FlsSimulator(const Scene& scene, const Scenario& s, double level_scale)
    : scene_(scene),
      model_(s.fls),
      mount_(s.fls_mount),
      noise_(s.noise),
      seed_(s.seed),
      binner_(rowRanges(model_)),
      rays_per_beam_(s.fls_sim.rays_azimuth * s.fls_sim.rays_elevation) {
    chain_.source_level = s.fls_sim.source_level;
    chain_.tvg_exponent = s.fls_sim.tvg_db_per_decade / 10.0;
    chain_.gain = std::pow(10.0, (kFlsBaseGainDb + s.fls_sim.gain_db) / 20.0);
    chain_.ray_weight = static_cast<double>(model_.rows()) / rays_per_beam_ * level_scale;

    // Stratified ray grid: ray centres of equal sub-cells of each beam.
    const int na = s.fls_sim.rays_azimuth, ne = s.fls_sim.rays_elevation;
    directions_.reserve(static_cast<std::size_t>(rays_per_beam_) * model_.cols());
    for (int c = 0; c < model_.cols(); ++c) {
        const double width = beamWidth(model_, c);
        for (int a = 0; a < na; ++a) {
            const double bearing = model_.bearingOfColumn(c) + ((a + 0.5) / na - 0.5) * width;
            for (int e = 0; e < ne; ++e) {
                const double elevation =
                    s.fls.elevation_min + (e + 0.5) / ne * (s.fls.elevation_max - s.fls.elevation_min);
                directions_.push_back(beamDirection(s.fls.tilt + elevation, bearing).cast<float>());  // Eq. 4
            }
        }
    }
}

FlsImage FlsSimulator::render(const Pose& vehicle, int64_t sequence, int threads) const {
    FlsImage image;
    image.rows = model_.rows();
    image.cols = model_.cols();
    image.data.assign(static_cast<std::size_t>(image.rows) * image.cols, 0);
    const Eigen::Isometry3d world_from_sensor = sensorToWorld(vehicle, mount_);
    parallelFor(model_.cols(), threads, [&](int col) { renderBeam(col, world_from_sensor, sequence, image); });
    return image;
}

void FlsSimulator::renderBeam(int col, const Eigen::Isometry3d& world_from_sensor, int64_t sequence,
                              FlsImage& image) const {
    const Eigen::Matrix3f rotation = world_from_sensor.linear().cast<float>();
    const Eigen::Vector3f origin = world_from_sensor.translation().cast<float>();
    std::vector<Eigen::Vector3f> dirs(rays_per_beam_);
    const Eigen::Vector3f* local = &directions_[static_cast<std::size_t>(col) * rays_per_beam_];
    for (int i = 0; i < rays_per_beam_; ++i) dirs[i] = rotation * local[i];

    std::vector<RayHit> hits(rays_per_beam_);
    scene_.cast(origin, dirs.data(), rays_per_beam_, 0.0f, static_cast<float>(binner_.maxRange()), hits.data());

    std::vector<double> energy(model_.rows(), 0.0);
    accumulateHits(scene_, hits.data(), rays_per_beam_, binner_, chain_, energy.data());
    Rng rng(noiseSeed(seed_, NoiseChannel::Fls, sequence, static_cast<uint32_t>(col)));
    energyToCounts(energy.data(), binner_, chain_, noise_, rng, image.data.data() + col, image.cols);
}

}  // namespace sonarfusion::sim
