#include "sonarfusion/fls_update.hpp"

#include <cmath>

namespace sonarfusion {

FlsUpdater::FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map)
    : model_(model), cfg_(cfg),
      increment_(static_cast<float>(logOddsFromProbability(cfg.p_occupied) * cfg.alpha_fls)) {
    world_direction_.resize(model.directions().size());
    if (cfg_.fls_once_per_frame) {
        slot_.assign(map.size(), 0u);
        const std::size_t max_points = static_cast<std::size_t>(model.rows()) * model.cols() * model.elevationSamples();
        const std::size_t cap = max_points < map.size() ? max_points : map.size();
        touched_.resize(cap);
        strongest_.resize(cap);
    }
}

FlsUpdateStats FlsUpdater::apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, VoxelMap& map) {
    FlsUpdateStats st;
    const Eigen::Matrix3f rot = world_from_sensor.linear().cast<float>();
    for (std::size_t i = 0; i < world_direction_.size(); ++i) world_direction_[i] = rot * model_.directions()[i];
    // Work relative to the map's min corner in voxel units: small numbers, float is exact enough.
    const float inv_res = static_cast<float>(1.0 / map.resolution());
    const Eigen::Vector3f sensor = ((world_from_sensor.translation() - map.origin()) / map.resolution()).cast<float>();
    const int nx = map.nx(), ny = map.ny(), nz = map.nz();
    const int nv = model_.elevationSamples();
    std::size_t n_touched = 0;
    VoxelMap::Writer out = map.writer();

    for (int row = 0; row < frame.rows; ++row) {
        const uint8_t* line = frame.data + static_cast<std::size_t>(row) * frame.cols;
        const float range = static_cast<float>(model_.rangeOfRow(row)) * inv_res;
        for (int col = 0; col < frame.cols; ++col) {
            const uint8_t intensity = line[col];
            if (intensity <= cfg_.fls_intensity_threshold) continue;  // paper 2.2: > 150 only
            ++st.pixels_above_threshold;
            const Eigen::Vector3f* dir = &world_direction_[static_cast<std::size_t>(col) * nv];
            for (int k = 0; k < nv; ++k) {
                const Eigen::Vector3f p = sensor + range * dir[k];  // Eq. 4, in voxel units
                // Bounds on the raw coordinates (NaN fails them); inside the grid
                // they are >= 0, where truncation equals floor() and is cheaper.
                if (!(p.x() >= 0.0f && p.y() >= 0.0f && p.z() >= 0.0f && p.x() < nx && p.y() < ny && p.z() < nz)) {
                    ++st.points_outside_map;
                    continue;
                }
                ++st.points_in_map;
                const std::size_t v = (static_cast<std::size_t>(static_cast<int>(p.z())) * ny +
                                       static_cast<std::size_t>(static_cast<int>(p.y()))) * nx +
                                      static_cast<std::size_t>(static_cast<int>(p.x()));
                if (!cfg_.fls_once_per_frame) {
                    // Eq. 6 per candidate point, then the clamp of Eq. 8.
                    out.add(v, increment_ * intensity / 255.0f);
                    out.setFlag(v, VoxelMap::kFlsTouched);
                    ++st.voxels_updated;
                    continue;
                }
                uint32_t& s = slot_[v];
                if (s == 0) {
                    touched_[n_touched] = static_cast<uint32_t>(v);
                    strongest_[n_touched] = intensity;
                    s = static_cast<uint32_t>(++n_touched);
                } else if (strongest_[s - 1] < intensity) {
                    strongest_[s - 1] = intensity;
                }
            }
        }
    }
    // Per-frame counting: each voxel gets Eq. 6 once, with its strongest intensity.
    for (std::size_t i = 0; i < n_touched; ++i) {
        const uint32_t v = touched_[i];
        out.add(v, increment_ * strongest_[i] / 255.0f);
        out.setFlag(v, VoxelMap::kFlsTouched);
        slot_[v] = 0;
    }
    if (cfg_.fls_once_per_frame) st.voxels_updated = static_cast<int>(n_touched);
    return st;
}

}  // namespace sonarfusion
