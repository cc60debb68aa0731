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

// DetectorConfig::fls_shadow_false_alarm: an object standing on the seabed
// hides the seabed behind it from the FLS, and the seabed's pixels go dark
// there for a run of rows. Inside the band of ranges at which every beam's
// elevation arc surely meets `seabed` (from the plane lowered by `margin` at
// the band's near end to the plane raised by it at the far end), pixels at or
// below `noise_level` are dark. The band is cut into 8 parts along each beam
// (the seabed's returns weaken with range); per part, the frame's own band
// pixels give the chance p that a pixel is dark and q that one after a dark
// pixel is dark too. A dark run that starts after a seabed return (a shadow
// begins behind something that returned) and ends at the next one or at the
// band's far end then has the chance p q^(L - 1) of its parts, and over the
// frame's N band pixels N p q^(L - 1) bounds how many such runs speckle makes
// per frame. The rarest run is a shadow when that is below `false_alarm`.
// With `like_water`, only a run whose mean pixel lies nearer the mean of the
// water column's dark pixels (nearer than the seabed could return on any ray
// of their beam) than that of the band's dark pixels counts: a shadow holds
// nothing but noise, a seabed turned away from the sonar still returns weakly.
// Returns the point where its first dark row meets the seabed plane (just
// behind the object), or nothing. No allocation.
[[nodiscard]] std::optional<Eigen::Vector3d> flsShadowOnSeabed(const FlsFrame& frame, const FlsModel& model,
                                                               const Eigen::Isometry3d& world_from_sensor,
                                                               const SeabedFit& seabed, double margin,
                                                               int noise_level, double false_alarm, bool like_water);

}  // namespace sonarfusion
