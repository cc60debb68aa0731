// FLS log-odds update (paper Eqs. 5-9): every pixel above the threshold votes
// for the voxels its elevation arc passes through; optionally the beam's
// water before its first return is carved (FLS space carving).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct FlsUpdateStats {
    int pixels_above_threshold = 0;
    int points_in_map = 0;
    int points_outside_map = 0;  // skipped, never written
    int voxels_updated = 0;      // occupied updates
    int voxels_freed = 0;        // free-space updates
};

class FlsUpdater {
public:
    // Scratch for per-frame counting and the arc tables are sized here, once.
    FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map);

    // The frame must already match the model (FlsModel::frameMatches).
    FlsUpdateStats apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, VoxelMap& map);

    // Eq. 5 times alpha_F: the increment for a pixel of intensity 255.
    [[nodiscard]] float fullScaleIncrement() const { return increment_; }
    // alpha_F * ln(P_f / (1 - P_f)): the free-space update (< 0).
    [[nodiscard]] float freeIncrement() const { return free_increment_; }
    // Candidate points an elevation arc at range r needs (N_v, or finer with
    // fls_arc_spacing_voxels); every arc uses arcSamples(maximum range).
    [[nodiscard]] int arcSamples(double range) const;
    [[nodiscard]] int samplesPerArc() const { return table_samples_; }

private:
    // Voxel of a point in voxel units relative to the map corner; -1 outside (NaN too).
    [[nodiscard]] static int64_t voxelOf(const Eigen::Vector3f& p, int nx, int ny, int nz);

    const FlsModel& model_;
    UpdateConfig cfg_;
    float increment_;       // delta L_o * alpha_F
    float free_increment_;  // alpha_F * ln(P_f / (1 - P_f))
    double arc_spacing_ = 0.0;  // m between arc samples; 0: N_v samples
    int table_samples_;         // elevation samples per column in the direction table
    std::vector<Eigen::Vector3f> sensor_direction_; // cols * table_samples_, sensor frame
    std::vector<Eigen::Vector3f> world_direction_;  // the same rotated into the map frame
    std::vector<uint32_t> slot_;                    // per voxel: 1 + index into touched_, 0 = untouched
    std::vector<uint32_t> touched_;                 // voxels hit or freed in this frame
    std::vector<uint8_t> strongest_;                // strongest intensity per touched voxel, 0 = freed
};

}  // namespace sonarfusion
