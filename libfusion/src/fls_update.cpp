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
    FlsUpdateStats st;
    const Eigen::Matrix3f rot = world_from_sensor.linear().cast<float>();
    for (std::size_t i = 0; i < world_direction_.size(); ++i) world_direction_[i] = rot * sensor_direction_[i];
    // Work relative to the map's min corner in voxel units: small numbers, float is exact enough.
    const float inv_res = static_cast<float>(1.0 / map.resolution());
    const Eigen::Vector3f sensor = ((world_from_sensor.translation() - map.origin()) / map.resolution()).cast<float>();
    const int nx = map.nx(), ny = map.ny(), nz = map.nz();
    const int table = table_samples_;
    const bool dedupe = cfg_.fls_once_per_frame || cfg_.fls_free_space;
    std::size_t n_touched = 0;
    VoxelMap::Writer out = map.writer();

    for (int row = 0; row < frame.rows; ++row) {
        const uint8_t* line = frame.data + static_cast<std::size_t>(row) * frame.cols;
        const float range = static_cast<float>(model_.rangeOfRow(row)) * inv_res;
        for (int col = 0; col < frame.cols; ++col) {
            const uint8_t intensity = line[col];
            if (intensity <= cfg_.fls_intensity_threshold) continue;  // paper 2.2: > 150 only
            ++st.pixels_above_threshold;
            const Eigen::Vector3f* dir = &world_direction_[static_cast<std::size_t>(col) * table];
            for (int k = 0; k < table; ++k) {
                const int64_t v = voxelOf(sensor + range * dir[k], nx, ny, nz);  // Eq. 4, in voxel units
                if (v < 0) {
                    ++st.points_outside_map;
                    continue;
                }
                ++st.points_in_map;
                if (!cfg_.fls_once_per_frame) {
                    // Eq. 6 per candidate point, then the clamp of Eq. 8.
                    out.add(v, increment_ * intensity / 255.0f);
                    out.setFlag(v, VoxelMap::kFlsTouched);
                    ++st.voxels_updated;
                    if (!dedupe) continue;  // else remember the hit, so free space skips it
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
    if (cfg_.fls_free_space) {
        // Per beam, the water before its first return: arcs stepped half a voxel
        // apart in range, up to a voxel diagonal short of that return (so no
        // voxel holding a point of the returning arc is carved). Voxels this
        // frame also hit keep only the hit.
        const float margin = std::sqrt(3.0f);
        const float r_min = static_cast<float>(model_.rangeOfRow(frame.rows - 1)) * inv_res;
        for (int col = 0; col < frame.cols; ++col) {
            float r_first = static_cast<float>(model_.rangeMax()) * inv_res;  // no return: all water
            for (int row = frame.rows - 1; row >= 0; --row)  // near to far (row 0 is far)
                if (frame.data[static_cast<std::size_t>(row) * frame.cols + col] > cfg_.fls_intensity_threshold) {
                    r_first = static_cast<float>(model_.rangeOfRow(row)) * inv_res;
                    break;
                }
            const Eigen::Vector3f* dir = &world_direction_[static_cast<std::size_t>(col) * table];
            for (float r = r_min; r < r_first - margin; r += 0.5f) {
                for (int k = 0; k < table; ++k) {
                    const int64_t v = voxelOf(sensor + r * dir[k], nx, ny, nz);
                    if (v < 0) continue;
                    uint32_t& s = slot_[v];
                    if (s != 0) continue;
                    touched_[n_touched] = static_cast<uint32_t>(v);
                    strongest_[n_touched] = 0;
                    s = static_cast<uint32_t>(++n_touched);
                }
            }
        }
    }
    // Per-frame counting: each voxel gets Eq. 6 once, with its strongest
    // intensity, or the free-space update once.
    for (std::size_t i = 0; i < n_touched; ++i) {
        const uint32_t v = touched_[i];
        if (strongest_[i] == 0) {
            out.add(v, free_increment_);
            ++st.voxels_freed;
        } else if (cfg_.fls_once_per_frame) {
            out.add(v, increment_ * strongest_[i] / 255.0f);
            out.setFlag(v, VoxelMap::kFlsTouched);
            ++st.voxels_updated;
        }  // else: every hit point was applied in the loop above
        slot_[v] = 0;
    }
    return st;
}

}  // namespace sonarfusion
