#include "sonarfusion/ps_carving.hpp"

#include <cmath>

#include "sonarfusion/voxel_walk.hpp"

namespace sonarfusion {

PsCarver::PsCarver(const PsModel& model, const UpdateConfig& cfg)
    : model_(model), cfg_(cfg),
      free_increment_(static_cast<float>(logOddsFromProbability(cfg.p_free))),
      hit_increment_(static_cast<float>(logOddsFromProbability(cfg.p_occupied))) {}

PsCarveStats PsCarver::apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                             VoxelMap& map) const {
    PsCarveStats st;
    const Eigen::Vector3d origin = world_from_sensor.translation();
    const float alpha = static_cast<float>(cfg_.alpha_ps);
    for (int k = 0; k < model_.fanSamples(); ++k) {
        const Eigen::Vector3d end = origin + world_from_sensor.linear() * (selected_range * model_.direction(head_angle, k));
        ++st.rays;
        VoxelMap::Writer out = map.writer();
        const WalkResult w = walkSegment(map, origin, end, [&](std::size_t v, double t) {
            out.add(v, free_increment_ * std::exp(-alpha * static_cast<float>(t)));  // Eq. 13
            out.setFlag(v, VoxelMap::kPsObserved);
        });
        st.voxels_carved += w.visited;
        if (w.end_in_map) {
            ++st.endpoints_in_map;
            map.setFlag(w.end_voxel, VoxelMap::kPsObserved);
            map.addPsEcho(w.end_voxel);
            if (cfg_.ps_endpoint_hits) map.add(w.end_voxel, hit_increment_);
        } else {
            ++st.endpoints_outside_map;
        }
    }
    return st;
}

}  // namespace sonarfusion
