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
        case Outcome::NavTimeJump: return "nav_time_jump";
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
    // Geometry, sizes and capacities: every number something is allocated from
    // or divided by (issue 10: inf ranges, NaN minimum range, 0 bins were taken).
    auto finite = [](double v) { return std::isfinite(v); };
    auto angle = [&](double a) { return finite(a) && std::fabs(a) <= M_PI; };
    const FlsGeometry& f = cfg.fls;
    if (!angle(f.fov_horizontal) || f.fov_horizontal <= 0.0) return "fls.fov_horizontal_deg must be in (0, 180]";
    if (!angle(f.elevation_min) || !angle(f.elevation_max) || f.elevation_max <= f.elevation_min)
        return "fls.elevation_min_deg must be below fls.elevation_max_deg, both finite";
    if (!angle(f.tilt)) return "fls.tilt_deg must be finite, |tilt| <= 180";
    if (!finite(f.range_min) || !finite(f.range_max) || f.range_min < 0.0 || f.range_max <= f.range_min ||
        f.range_max > 1000.0)
        return "fls.range_min/range_max must satisfy 0 <= range_min < range_max <= 1000 m";
    if (f.beams < 1 || f.beams > kMaxFlsBeams) return "fls.beams must be in 1..4096";
    if (f.rows < 2 || f.rows > kMaxFlsRows) return "fls.rows must be in 2..16384";
    if (f.elevation_samples < 1 || f.elevation_samples > 1024) return "fls.elevation_samples must be in 1..1024";
    const PsGeometry& p = cfg.ps;
    if (!angle(p.fan_min) || !angle(p.fan_max) || p.fan_max <= p.fan_min)
        return "ps.fan_min_deg must be below ps.fan_max_deg, both finite";
    if (!angle(p.head_min) || !angle(p.head_max) || p.head_max < p.head_min)
        return "ps.head_min_deg must not be above ps.head_max_deg, both finite";
    if (!angle(p.tilt)) return "ps.tilt_deg must be finite, |tilt| <= 180";
    if (!finite(p.range_min) || !finite(p.range_max) || p.range_min < 0.0 || p.range_max <= p.range_min ||
        p.range_max > 1000.0)
        return "ps.range_min/range_max must satisfy 0 <= range_min < range_max <= 1000 m";
    if (p.bins < 2 || p.bins > kMaxPsBins) return "ps.bins must be in 2..65536";
    if (p.fan_samples < 1 || p.fan_samples > 1024) return "ps.fan_samples must be in 1..1024";
    const MapConfig& m = cfg.map;
    if (m.nx < 1 || m.ny < 1 || m.nz < 1 || m.nx > kMaxMapCells || m.ny > kMaxMapCells || m.nz > kMaxMapCells)
        return "map.nx/ny/nz must be in 1..4096";
    if (!finite(m.resolution) || m.resolution <= 0.0) return "map.resolution must be a positive number";
    if (!(m.clamp_min < 0.0f && m.clamp_max > 0.0f) || !std::isfinite(m.clamp_min) || !std::isfinite(m.clamp_max))
        return "map.clamp_min must be < 0 < map.clamp_max";
    if (!(s.min_range >= 0.0) || !finite(s.min_range)) return "ps_selection.min_range must be finite and >= 0";
    if (s.min_peak_intensity < 0 || s.min_peak_intensity > 255) return "ps_selection.min_peak_intensity must be in 0..255";
    const DetectorConfig& d = cfg.detector;
    if (!(d.seabed_radius > 0.0) || !finite(d.seabed_radius)) return "detector.seabed_radius must be > 0";
    if (d.seabed_capacity < 3 || d.seabed_capacity > 1000000) return "detector.seabed_capacity must be in 3..1000000";
    if (d.min_seabed_echoes < 3 || d.min_seabed_echoes > d.seabed_capacity)
        return "detector.min_seabed_echoes must be in 3..seabed_capacity";
    if (!(d.min_rise >= 0.0) || !finite(d.min_rise) || !(d.rise_sigmas >= 0.0) || !finite(d.rise_sigmas))
        return "detector.min_rise and detector.rise_sigmas must be finite and >= 0";
    if (!(d.cluster_radius > 0.0) || !finite(d.cluster_radius)) return "detector.cluster_radius must be > 0";
    if (d.risen_capacity < 1 || d.risen_capacity > 1000000) return "detector.risen_capacity must be in 1..1000000";
    if (d.min_risen_echoes < 1 || d.min_risen_echoes > d.risen_capacity)
        return "detector.min_risen_echoes must be in 1..risen_capacity";
    if (!(g.occupied_probability > 0.0 && g.occupied_probability < 1.0))
        return "segmentation.occupied_probability must be in (0, 1)";
    if (!(g.min_object_height >= 0.0) || !finite(g.min_object_height) || !(g.baseline_window > 0.0) ||
        !finite(g.baseline_window))
        return "segmentation.min_object_height must be >= 0 and segmentation.baseline_window > 0";
    if (g.max_objects < 1 || g.max_objects > 65535) return "segmentation.max_objects must be in 1..65535";
    if (g.min_object_voxels < 1) return "segmentation.min_object_voxels must be >= 1";
    if (cfg.nav_buffer_capacity < 2 || cfg.nav_buffer_capacity > 1000000) return "nav.buffer_capacity must be in 2..1000000";
    if (cfg.nav_timeline_confirm < 1 || cfg.nav_timeline_confirm > kMaxNavTimelineConfirm)
        return "nav.timeline_confirm must be in 1..64";
    return {};
}

std::size_t estimatedMemoryBytes(const MapperConfig& cfg) {
    // Per voxel (docs/algorithm.md, "Memory"): 5 B map, 13 B FLS frame scratch,
    // 10 B segmentation; plus the FLS direction tables and the fixed rings.
    const double voxels = static_cast<double>(cfg.map.nx) * cfg.map.ny * cfg.map.nz;
    const double columns = static_cast<double>(cfg.map.nx + 1) * (cfg.map.ny + 1);
    const double fls = static_cast<double>(cfg.fls.beams) * cfg.fls.rows * 8.0 + (1 << 20);
    const double bytes = voxels * 28.0 + columns * 8.0 * 13 + fls + cfg.nav_buffer_capacity * 64.0 +
                         (cfg.detector.seabed_capacity + cfg.detector.risen_capacity) * 32.0;
    return bytes > 1e18 ? static_cast<std::size_t>(1e18) : static_cast<std::size_t>(bytes);
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

namespace {
// b follows a on one timeline: strictly later, by at most max_gap (unsigned
// difference: utimes come off the network and may be anything).
bool continuous(int64_t a, int64_t b, int64_t max_gap) {
    return b > a && static_cast<uint64_t>(b) - static_cast<uint64_t>(a) <= static_cast<uint64_t>(max_gap);
}
}  // namespace

bool Mapper::navWouldReset(const TimedPose& nav) const {
    if (!nav.pose.isFinite() || nav_.empty()) return false;
    const int64_t newest = nav_.newest().utime;
    if (continuous(newest, nav.utime, cfg_.max_nav_gap_us)) return false;
    if (nav.utime <= newest && static_cast<uint64_t>(newest) - static_cast<uint64_t>(nav.utime) <=
                                   static_cast<uint64_t>(cfg_.max_nav_gap_us))
        return false;  // reordered or repeated: refused, not a new timeline
    const bool extends = nav_candidate_count_ > 0 &&
                         continuous(nav_candidate_[nav_candidate_count_ - 1].utime, nav.utime, cfg_.max_nav_gap_us);
    return (extends ? nav_candidate_count_ + 1 : 1) >= cfg_.nav_timeline_confirm;
}

Outcome Mapper::addNav(const TimedPose& nav) {
    ++counters_.nav_in;
    if (!nav.pose.isFinite()) return count(Outcome::NavNonFinite);
    if (!nav_.empty()) {
        const int64_t newest = nav_.newest().utime;
        if (!continuous(newest, nav.utime, cfg_.max_nav_gap_us)) {
            if (nav.utime <= newest && static_cast<uint64_t>(newest) - static_cast<uint64_t>(nav.utime) <=
                                           static_cast<uint64_t>(cfg_.max_nav_gap_us))
                return count(Outcome::NavOutOfOrder);  // reordered or repeated within one timeline
            // A jump ahead or a step back beyond any gap we interpolate over: one
            // glitch (an INT64_MAX stamp) must not end mapping, and a real clock
            // step must not be interpolated against the old timeline. Hold it as a
            // candidate timeline until confirmed.
            const bool extends = nav_candidate_count_ > 0 &&
                                 continuous(nav_candidate_[nav_candidate_count_ - 1].utime, nav.utime,
                                            cfg_.max_nav_gap_us);
            if (!extends) nav_candidate_count_ = 0;
            nav_candidate_[nav_candidate_count_++] = nav;
            if (nav_candidate_count_ < cfg_.nav_timeline_confirm) return count(Outcome::NavTimeJump);
            nav_.clear();
            for (int i = 0; i < nav_candidate_count_; ++i) {
                (void)nav_.add(nav_candidate_[i]);
                track_axis_.add(nav_candidate_[i].pose.yaw);
            }
            // The held samples were counted nav_time_jump on arrival; now they are used.
            counters_.by_outcome[static_cast<int>(Outcome::NavTimeJump)] -= nav_candidate_count_ - 1;
            counters_.by_outcome[static_cast<int>(Outcome::Used)] += nav_candidate_count_ - 1;
            counters_.nav_used += nav_candidate_count_;
            nav_candidate_count_ = 0;
            ++counters_.nav_timeline_resets;
            return count(Outcome::Used);
        }
    }
    nav_candidate_count_ = 0;  // the current timeline goes on: whatever was held was a glitch
    (void)nav_.add(nav);
    track_axis_.add(nav.pose.yaw);
    ++counters_.nav_used;
    return count(Outcome::Used);
}

std::optional<Pose> Mapper::navPoseAt(int64_t utime) const {
    Pose p;
    if (nav_.poseAt(utime, p) != PoseLookup::Ok) return std::nullopt;
    return p;
}

std::optional<int64_t> Mapper::newestNavUtime() const {
    if (nav_.empty()) return std::nullopt;
    return nav_.newest().utime;
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


void Mapper::saveState(StateWriter& w) const {
    map_.saveState(w);
    detector_.saveState(w);
    nav_.saveState(w);
    w.pod(nav_candidate_count_);
    for (int i = 0; i < nav_candidate_count_; ++i) saveTimedPose(w, nav_candidate_[i]);
    track_axis_.saveState(w);
    w.pod(counters_);
}

bool Mapper::loadState(StateReader& r) {
    int held = 0;
    if (!map_.loadState(r) || !detector_.loadState(r) || !nav_.loadState(r) || !r.pod(held) || held < 0 ||
        held >= cfg_.nav_timeline_confirm)
        return false;
    for (int i = 0; i < held; ++i)
        if (!loadTimedPose(r, nav_candidate_[i])) return false;
    nav_candidate_count_ = held;
    return track_axis_.loadState(r) && r.pod(counters_);
}

std::size_t Mapper::stateBytesBound() const {
    const std::size_t pose = sizeof(int64_t) + 6 * sizeof(double);
    return 64 + map_.size() * (sizeof(float) + 1) + 24 * 2 +
           static_cast<std::size_t>(cfg_.detector.seabed_capacity + cfg_.detector.risen_capacity) * 24 + 64 +
           static_cast<std::size_t>(cfg_.nav_buffer_capacity) * pose + 16 +
           static_cast<std::size_t>(kMaxNavTimelineConfirm) * pose + 64 + sizeof(MapperCounters);
}

}  // namespace sonarfusion
