// PS carving (paper Eqs. 12-13): every voxel between the sensor and each of
// the N_h fan candidates at the selected range r_s gets a free-space update
// that is strongest near the sensor and fades toward the echo.
#pragma once

#include <Eigen/Geometry>

#include "sonarfusion/config.hpp"
#include "sonarfusion/ps_model.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct PsCarveStats {
    int rays = 0;
    int voxels_carved = 0;
    int endpoints_in_map = 0;
    int endpoints_outside_map = 0;
};

class PsCarver {
public:
    PsCarver(const PsModel& model, const UpdateConfig& cfg);

    // Carves the fan at head angle phi_p with selected range r_s (Eq. 11 points).
    PsCarveStats apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                       VoxelMap& map) const;

    [[nodiscard]] float freeIncrement() const { return free_increment_; }  // Eq. 12

private:
    const PsModel& model_;
    UpdateConfig cfg_;
    float free_increment_;  // delta L_f < 0
    float hit_increment_;   // delta L_o, for the carve_only end-point hits
};

}  // namespace sonarfusion
