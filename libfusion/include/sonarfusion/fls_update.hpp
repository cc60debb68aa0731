// FLS log-odds update (paper Eqs. 5-9): every pixel above the threshold votes
// for the voxel holding each of its N_v elevation candidates.
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
    int voxels_updated = 0;
};

class FlsUpdater {
public:
    // Scratch for per-frame counting is sized for the map here, once.
    FlsUpdater(const FlsModel& model, const UpdateConfig& cfg, const VoxelMap& map);

    // The frame must already match the model (FlsModel::frameMatches).
    FlsUpdateStats apply(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor, VoxelMap& map);

    // Eq. 5 times alpha_F: the increment for a pixel of intensity 255.
    [[nodiscard]] float fullScaleIncrement() const { return increment_; }

private:
    const FlsModel& model_;
    UpdateConfig cfg_;
    float increment_;  // delta L_o * alpha_F
    std::vector<Eigen::Vector3f> world_direction_;  // model directions rotated into the map frame
    std::vector<uint32_t> slot_;                    // per voxel: 1 + index into touched_, 0 = untouched
    std::vector<uint32_t> touched_;                 // voxels hit in this frame
    std::vector<uint8_t> strongest_;                // strongest intensity per touched voxel
};

}  // namespace sonarfusion
