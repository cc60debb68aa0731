#include "sonarfusion/fls_update.hpp"

#include <algorithm>
#include <cmath>

namespace sonarfusion {

FlsUpdater::FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map)
    : model_(model), cfg_(cfg),
      increment_(static_cast<float>(logOddsFromProbability(cfg.p_occupied) * cfg.alpha_fls)),
      free_increment_(static_cast<float>(logOddsFromProbability(cfg.p_free) * cfg.alpha_fls)) {
    if (cfg.fls_arc_spacing_voxels > 0.0) arc_spacing_ = cfg.fls_arc_spacing_voxels * map.resolution();
    table_samples_ = arcSamples(model.rangeMax());
    // One direction table per arc length n = N_v .. table_samples_, each with
    // n evenly spaced elevations, so every range gets exactly the samples it
    // needs (a subset of one finer table leaves gaps).
    const int nv = model.elevationSamples();
    table_offset_.assign(table_samples_ + 1, 0);
    std::size_t total = 0;
    for (int n = nv; n <= table_samples_; ++n) {
        table_offset_[n] = total;
        total += static_cast<std::size_t>(model.cols()) * n;
    }
    sensor_direction_.resize(total);
    const double lo = model.elevationMin(), hi = model.elevationMax();
    for (int n = nv; n <= table_samples_; ++n)
        for (int c = 0; c < model.cols(); ++c)
            for (int k = 0; k < n; ++k)
                sensor_direction_[table_offset_[n] + static_cast<std::size_t>(c) * n + k] =
                    n == nv && !(arc_spacing_ > 0.0) ? model.direction(c, k)  // Eq. 3 exactly
                                                     : model.directionAt(c, n == 1 ? 0.5 * (lo + hi) : lo + k * (hi - lo) / (n - 1));
    row_samples_.resize(model.rows());
    for (int r = 0; r < model.rows(); ++r) row_samples_[r] = arcSamples(model.rangeOfRow(r));
    world_direction_.resize(sensor_direction_.size());
    if (cfg_.fls_once_per_frame || cfg_.fls_free_space) {
        slot_.assign(map.size(), 0u);
        touched_.resize(map.size());
        strongest_.resize(map.size());
    }
}

int FlsUpdater::arcSamples(double range) const {
    const int nv = model_.elevationSamples();
    if (!(arc_spacing_ > 0.0)) return nv;
    const double arc = std::max(0.0, range) * (model_.elevationMax() - model_.elevationMin());
    return std::max(nv, static_cast<int>(std::ceil(arc / arc_spacing_)) + 1);
}

int64_t FlsUpdater::voxelOf(const Eigen::Vector3f& p, int nx, int ny, int nz) {
    // Bounds on the raw coordinates (NaN fails them); inside the grid they are
    // >= 0, where truncation equals floor() and is cheaper.
    if (!(p.x() >= 0.0f && p.y() >= 0.0f && p.z() >= 0.0f && p.x() < nx && p.y() < ny && p.z() < nz)) return -1;
    return (static_cast<int64_t>(static_cast<int>(p.z())) * ny + static_cast<int>(p.y())) * nx +
           static_cast<int>(p.x());
}

FlsUpdateStats FlsUpdater::apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, VoxelMap& map) {
    MapWriterSink sink(map);
    return apply(frame, world_from_sensor, map, sink);
}

}  // namespace sonarfusion
