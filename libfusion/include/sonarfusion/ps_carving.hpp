// PS carving (paper Eqs. 12-13): every voxel between the sensor and each of
// the N_h fan candidates at the selected range r_s gets a free-space update
// that is strongest near the sensor and fades toward the echo.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "sonarfusion/config.hpp"
#include "sonarfusion/ps_model.hpp"
#include "sonarfusion/update_sink.hpp"
#include "sonarfusion/voxel_map.hpp"
#include "sonarfusion/voxel_walk.hpp"

namespace sonarfusion {

struct PsCarveStats {
    int rays = 0;
    int voxels_carved = 0;  // visited by the walk (carved or spared)
    int voxels_spared = 0;  // held PS echoes for enough of the rays that reached them (not carved)
    int endpoints_in_map = 0;
    int endpoints_outside_map = 0;
};

// Where a ping's carving stops: the nearer of its nearest group's first bin
// and its first bin that could be an echo (firstEchoBin with `noise_sigmas`,
// and a window of `echo_window` m of range, at least 2 bins, when > 0);
// negative (carve up to the selected echo) when that is the echo's own bin or
// noise_sigmas is 0 (UpdateConfig::ps_carve_noise_sigmas, ps_carve_echo_window_voxels).
[[nodiscard]] double carveStopRange(const PsPing& ping, const PsEchoGroup& group, const PsSelectionConfig& selection,
                                    double noise_sigmas, double echo_window = 0.0);

// UpdateConfig::ps_carve_spare_echo_share: whether a ray spares (does not carve)
// a voxel where `echoes` PS echoes ended and `crossings` rays crossed it so far:
// E >= ps_carve_spare_min_echoes and E >= share (E + C). Counts as the map keeps
// them (saturating); the share 0 spares nothing (the paper's Eq. 13).
[[nodiscard]] inline bool sparesSurfaceVoxel(const UpdateConfig& cfg, int echoes, int crossings) {
    const double share = cfg.ps_carve_spare_echo_share;
    return share > 0.0 && echoes >= cfg.ps_carve_spare_min_echoes && (1.0 - share) * echoes >= share * crossings;
}

class PsCarver {
public:
    PsCarver(const PsModel& model, const UpdateConfig& cfg);

    // Carves the fan at head angle phi_p with selected range r_s (Eq. 11
    // points). echo_strength is the selected bin's intensity / 255: with
    // ps_endpoint_hits, the voxel holding each fan candidate gets
    // delta L_o * echo_strength, the PS echo weighted like an FLS pixel (Eq. 6).
    PsCarveStats apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                       VoxelMap& map, double echo_strength = 1.0, double carve_range = -1.0) const;
    // carve_range (<= selected_range; negative: selected_range) is where the
    // free-space updates stop; the echo stays at selected_range.
    // The same updates, in the same order, handed to `sink` (update_sink.hpp).
    template <class Sink>
    PsCarveStats apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                       const VoxelMap& map, Sink& sink, double echo_strength = 1.0, double carve_range = -1.0) const;

    [[nodiscard]] float freeIncrement() const { return free_increment_; }  // Eq. 12

private:
    const PsModel& model_;
    UpdateConfig cfg_;
    float free_increment_;  // delta L_f < 0
    float hit_increment_;   // delta L_o, for the carve_only end-point hits
};

template <class Sink>
PsCarveStats PsCarver::apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                             const VoxelMap& map, Sink& sink, double echo_strength, double carve_range) const {
    PsCarveStats st;
    const float hit = hit_increment_ * static_cast<float>(echo_strength);
    const Eigen::Vector3d origin = world_from_sensor.translation();
    const float alpha = static_cast<float>(cfg_.alpha_ps);
    const bool shorter = carve_range >= 0.0 && carve_range < selected_range;
    // Eq. 13's t stays the fraction of the echo's range, however far the carving goes.
    const float t_scale = shorter ? static_cast<float>(carve_range / selected_range) : 1.0f;
    const bool spare = cfg_.ps_carve_spare_echo_share > 0.0;
    for (int k = 0; k < model_.fanSamples(); ++k) {
        const Eigen::Vector3d dir = world_from_sensor.linear() * model_.direction(head_angle, k);
        const Eigen::Vector3d end = origin + selected_range * dir;
        const Eigen::Vector3d carve_end = shorter ? Eigen::Vector3d(origin + carve_range * dir) : end;
        ++st.rays;
        sink.ray(origin, carve_end, end);
        const WalkResult w = walkSegment(map, origin, carve_end, [&](std::size_t v, double t) {
            const bool spared = spare && sparesSurfaceVoxel(cfg_, map.psEchoCount(v), map.psCrossings(v));
            sink.crossed(v);
            if (spared) {
                ++st.voxels_spared;
                return;
            }
            sink.add(v, free_increment_ * std::exp(-alpha * t_scale * static_cast<float>(t)), VoxelMap::kPsObserved);  // Eq. 13
        });
        st.voxels_carved += w.visited;
        VoxelIndex end_index;
        const bool end_in_map = shorter ? map.worldToIndex(end, end_index) : w.end_in_map;
        if (end_in_map) {
            const std::size_t end_voxel = shorter ? map.linear(end_index) : w.end_voxel;
            ++st.endpoints_in_map;
            sink.echo(end_voxel);
            if (cfg_.ps_endpoint_hits) sink.add(end_voxel, hit, VoxelMap::kPsObserved);
        } else {
            ++st.endpoints_outside_map;
        }
    }
    return st;
}

}  // namespace sonarfusion
