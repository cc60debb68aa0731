#include "sonarfusion/mapper.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sonarfusion {

std::string_view outcomeName(Outcome o) {
    switch (o) {
        case Outcome::Used: return "used";
        case Outcome::NavNonFinite: return "nav_non_finite";
        case Outcome::NavOutOfOrder: return "nav_out_of_order";
        case Outcome::NoPose: return "no_pose";
        case Outcome::NavGapTooLarge: return "nav_gap_too_large";
        case Outcome::FlsSizeMismatch: return "fls_size_mismatch";
        case Outcome::FlsBeforeMap: return "fls_before_map";
        case Outcome::FlsDisabled: return "fls_disabled";
        case Outcome::PsEmpty: return "ps_empty";
        case Outcome::PsBadGeometry: return "ps_bad_geometry";
        case Outcome::PsNoEcho: return "ps_no_echo";
        case Outcome::kCount: break;
    }
    return "unknown";
}

std::string validateConfig(const MapperConfig& cfg) {
    const UpdateConfig& u = cfg.update;
    auto open01 = [](double p) { return p > 0.0 && p < 1.0; };
    if (!open01(u.p_occupied) || u.p_occupied <= 0.5) return "update.p_occupied must be in (0.5, 1)";
    if (!open01(u.p_free) || u.p_free >= 0.5) return "update.p_free must be in (0, 0.5)";
    if (!(u.alpha_fls > 0.0) || !std::isfinite(u.alpha_fls)) return "update.alpha_fls must be > 0";
    if (!(u.alpha_ps >= 0.0) || !std::isfinite(u.alpha_ps)) return "update.alpha_ps must be >= 0";
    if (u.fls_intensity_threshold < 0 || u.fls_intensity_threshold > 255)
        return "update.fls_intensity_threshold must be in 0..255";
    const PsSelectionConfig& s = cfg.ps_selection;
    if (!(s.group_threshold >= 0.0 && s.group_threshold < 1.0)) return "ps_selection.group_threshold must be in [0, 1)";
    if (cfg.max_nav_gap_us <= 0) return "max_nav_gap_us must be > 0";
    // The issue-9 rules: sizes they allocate from, and shares.
    if (!(u.fls_arc_spacing_voxels == 0.0 || (u.fls_arc_spacing_voxels >= 0.25 && u.fls_arc_spacing_voxels <= 100.0)))
        return "update.fls_arc_spacing_voxels must be 0 (N_v samples) or in [0.25, 100]";
    const SegmentationConfig& g = cfg.segmentation;
    if (!(g.ps_echo_min_fraction >= 0.0 && g.ps_echo_min_fraction <= 1.0))
        return "segmentation.ps_echo_min_fraction must be in [0, 1]";
    if (g.ps_echo_min_count < 1) return "segmentation.ps_echo_min_count must be >= 1";
    if (g.fls_only_extension < 0 || g.fls_only_extension > 255)
        return "segmentation.fls_only_extension must be in 0..255";
    return {};
}

namespace {
const MapperConfig& checked(const MapperConfig& cfg) {
    const std::string err = validateConfig(cfg);
    if (!err.empty()) throw std::invalid_argument("mapper config: " + err);
    return cfg;
}
}  // namespace

Mapper::Mapper(const MapperConfig& cfg)
    : cfg_(checked(cfg)), map_(cfg.map), fls_model_(cfg.fls), ps_model_(cfg.ps),
      fls_updater_(fls_model_, cfg.update, map_), ps_carver_(ps_model_, cfg.update), detector_(cfg.detector),
      segmenter_(cfg.segmentation, cfg.update.require_ps_observation, map_),
      nav_(cfg.nav_buffer_capacity, cfg.max_nav_gap_us) {}

Outcome Mapper::count(Outcome o) {
    ++counters_.by_outcome[static_cast<int>(o)];
    return o;
}

Outcome Mapper::lookupPose(int64_t utime, Pose& out) const {
    switch (nav_.poseAt(utime, out)) {
        case PoseLookup::Ok: return Outcome::Used;
        case PoseLookup::NoBracket: return Outcome::NoPose;
        case PoseLookup::GapTooLarge: return Outcome::NavGapTooLarge;
    }
    return Outcome::NoPose;
}

Outcome Mapper::addNav(const TimedPose& nav) {
    ++counters_.nav_in;
    switch (nav_.add(nav)) {
        case NavBuffer::AddResult::NonFinite: return count(Outcome::NavNonFinite);
        case NavBuffer::AddResult::OutOfOrder: return count(Outcome::NavOutOfOrder);
        case NavBuffer::AddResult::Ok: break;
    }
    track_axis_.add(nav.pose.yaw);
    ++counters_.nav_used;
    return count(Outcome::Used);
}

Outcome Mapper::addFls(const FlsFrame& frame) {
    ++counters_.fls_in;
    if (!fls_model_.frameMatches(frame)) return count(Outcome::FlsSizeMismatch);
    if (!cfg_.update.fls_enabled) return count(Outcome::FlsDisabled);
    Pose pose;
    if (Outcome o = lookupPose(frame.utime, pose); o != Outcome::Used) return count(o);
    if (!map_.initialised()) return count(Outcome::FlsBeforeMap);
    const FlsUpdateStats st = fls_updater_.apply(frame, sensorToWorld(pose, cfg_.fls_mount), map_);
    counters_.fls_points_outside_map += st.points_outside_map;
    ++counters_.fls_used;
    return count(Outcome::Used);
}

Outcome Mapper::addPs(const PsPing& ping) {
    ++counters_.ps_in;
    switch (validatePing(ping)) {
        case PsPingError::Empty: return count(Outcome::PsEmpty);
        case PsPingError::BadGeometry: return count(Outcome::PsBadGeometry);
        case PsPingError::None: break;
    }
    Pose pose;
    if (Outcome o = lookupPose(ping.utime, pose); o != Outcome::Used) return count(o);
    const Eigen::Isometry3d world_from_sensor = sensorToWorld(pose, cfg_.ps_mount);

    if (!map_.initialised()) {
        // Paper 2.1: the strongest echo of the ping feeds the rising-edge detector.
        const std::optional<int> bin = maxIntensityBin(ping, cfg_.ps_selection);
        if (!bin) return count(Outcome::PsNoEcho);
        const Eigen::Vector3d echo =
            world_from_sensor * (rangeOfBin(ping, *bin) * ps_model_.centreDirection(ping.head_angle));
        if (detector_.addEchoPoint(echo)) {
            map_.initialiseAt(*detector_.detection());
            ++counters_.map_initialisations;
        }
        ++counters_.ps_used;
        return count(Outcome::Used);
    }

    // Paper 2.3: closest-group range, then carving (Eqs. 10-13).
    const std::optional<int> bin = selectClosestGroup(ping, cfg_.ps_selection);
    if (!bin) return count(Outcome::PsNoEcho);
    if (cfg_.update.ps_carving_enabled) {
        const PsCarveStats st = ps_carver_.apply(ping.head_angle, rangeOfBin(ping, *bin), world_from_sensor, map_,
                                                 ping.intensity[*bin] / 255.0);
        counters_.ps_endpoints_outside_map += st.endpoints_outside_map;
    }
    ++counters_.ps_used;
    return count(Outcome::Used);
}

const SegmentationStats& Mapper::segment() {
    segmenter_.setAlongTrack(track_axis_.axis());
    return segmenter_.run(map_);
}

void Mapper::initialiseMapAt(const Eigen::Vector3d& centre) {
    map_.initialiseAt(centre);
    ++counters_.map_initialisations;
}

}  // namespace sonarfusion
