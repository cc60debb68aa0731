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
    if (arc_spacing_ > 0.0) {
        sensor_direction_.resize(static_cast<std::size_t>(model.cols()) * table_samples_);
        const double lo = model.elevationMin(), hi = model.elevationMax();
        for (int c = 0; c < model.cols(); ++c)
            for (int k = 0; k < table_samples_; ++k)
                sensor_direction_[static_cast<std::size_t>(c) * table_samples_ + k] = model.directionAt(
                    c, table_samples_ == 1 ? 0.5 * (lo + hi) : lo + k * (hi - lo) / (table_samples_ - 1));
    } else {
        sensor_direction_ = model.directions();  // Eq. 3: N_v samples
    }
    world_direction_.resize(sensor_direction_.size());
    if (cfg_.fls_once_per_frame || cfg_.fls_free_space) {
        slot_.assign(map.size(), 0u);
        touched_.resize(map.size());
        strongest_.resize(map.size());
    }
}

// Every arc uses the samples that keep the longest one (at the maximum range)
// within the spacing: nearer arcs are sampled finer than needed, which the
// per-frame counting absorbs, and no subset of the table can leave a gap.
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
