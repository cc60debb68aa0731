#include "sonarfusion/ps_carving.hpp"

#include <cmath>


namespace sonarfusion {

PsCarver::PsCarver(const PsModel& model, const UpdateConfig& cfg)
    : model_(model), cfg_(cfg),
      free_increment_(static_cast<float>(logOddsFromProbability(cfg.p_free))),
      hit_increment_(static_cast<float>(logOddsFromProbability(cfg.p_occupied))) {}

PsCarveStats PsCarver::apply(double head_angle, double selected_range, const Eigen::Isometry3d& world_from_sensor,
                             VoxelMap& map, double echo_strength) const {
    MapWriterSink sink(map);
    return apply(head_angle, selected_range, world_from_sensor, map, sink, echo_strength);
}

}  // namespace sonarfusion
