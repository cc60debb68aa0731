// The FLS's evidence for object detection (DetectorConfig::fls_nearer_than_seabed):
// a return from nearer than the seabed could return on any ray of its beam's
// elevation arc comes from something standing above the seabed. The PS sees
// only its ±10 deg fan; the FLS's ±14.5 deg fan reaches objects beside it.
#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/seabed_fit.hpp"

namespace sonarfusion {

// The mean world position (NED) of the frame's pixels above `vote_threshold`
// whose range is shorter than the nearest range at which any ray of their
// beam's arc (its two edges and its centre) meets `seabed` raised by
// `margin`, each placed on its arc's centre line; nothing when the frame has
// none. No allocation.
[[nodiscard]] std::optional<Eigen::Vector3d> flsReturnNearerThanSeabed(const FlsFrame& frame, const FlsModel& model,
                                                                       const Eigen::Isometry3d& world_from_sensor,
                                                                       const SeabedFit& seabed, int vote_threshold,
                                                                       double margin);

}  // namespace sonarfusion
