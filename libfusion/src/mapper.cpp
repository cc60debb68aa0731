#include "sonarfusion/mapper.hpp"

#include "sonarfusion/fls_detection.hpp"

#include <algorithm>
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
        case Outcome::FlsBadGeometry: return "fls_bad_geometry";
        case Outcome::FlsGeometryNotCached: return "fls_geometry_not_cached";
        case Outcome::kCount: break;
    }
    return "unknown";
}

// One validator: each struct's own validate() (config.hpp, src/config.cpp).
std::string validateConfig(const MapperConfig& cfg) {
    const std::optional<ConfigIssue> issue = cfg.validate();
    return issue ? issue->message() : std::string();
}

namespace {
// Per-ping FLS geometry: a frame's window may reach one configured bin past the
// configured maximum range, its aperture this far past each configured limit.
constexpr double kFlsApertureTol = 0.5 * kDegToRad;
// A retired published box (its map reopened): lo above hi, so it overlaps nothing.
constexpr double kRetiredBox = 1e30;
double flsRangeTolerance(const FlsModel& m) {
    return (m.rangeMax() - m.rangeOfRow(m.rows() - 1)) / (m.rows() - 1);
}
// Samples of the longest arc any accepted geometry has (capacity of the cache's tables).
int flsMaxArcSamples(const MapperConfig& cfg, const FlsModel& m) {
    const double spacing = cfg.update.fls_arc_spacing_voxels > 0.0 ? cfg.update.fls_arc_spacing_voxels * cfg.map.resolution : 0.0;
    return FlsUpdater::arcSamplesFor(m.rangeMax() + flsRangeTolerance(m),
                                     cfg.fls.elevation_max - cfg.fls.elevation_min + 2.0 * kFlsApertureTol,
                                     cfg.fls.elevation_samples, spacing) + 1;  // + 1: rounding
}
}  // namespace

std::size_t estimatedMemoryBytes(const MapperConfig& cfg) {
    // Per voxel (docs/algorithm.md, "Memory"): 9 B map, 10 B FLS frame scratch,
    // 10 B segmentation; plus the FLS direction tables and the fixed rings.
    const double voxels = static_cast<double>(cfg.map.nx) * cfg.map.ny * cfg.map.nz;
    const double columns = static_cast<double>(cfg.map.nx + 1) * (cfg.map.ny + 1);
    // The FLS arc tables, per cached geometry (fls.max_geometries) plus their
    // rotated copy: beams x (sum of n over the arc lengths n) unit vectors each.
    const double spacing = cfg.update.fls_arc_spacing_voxels > 0.0 ? cfg.update.fls_arc_spacing_voxels * cfg.map.resolution : 0.0;
    const double n_max = FlsUpdater::arcSamplesFor(cfg.fls.range_max * 1.01 + 1.0,
                                                   cfg.fls.elevation_max - cfg.fls.elevation_min + 2.0 * kFlsApertureTol,
                                                   cfg.fls.elevation_samples, spacing) + 1.0;
    const double arc_vectors = static_cast<double>(cfg.fls.beams) * 0.5 * n_max * (n_max + 1.0);
    const double fls = static_cast<double>(cfg.fls.beams) * cfg.fls.rows * 8.0 + (1 << 20) +
                       arc_vectors * 12.0 * (cfg.fls_max_geometries + 1) +
                       (cfg.fls_max_geometries - 1) * (static_cast<double>(cfg.fls.rows + cfg.fls.beams) * 8.0 +
                                                       static_cast<double>(cfg.fls.beams) * cfg.fls.elevation_samples * 12.0);
    const double bytes = voxels * (20.0 + 9.0 * cfg.survey.max_maps) + columns * 8.0 * 13 + fls + cfg.nav_buffer_capacity * 64.0 +
                         // Per seabed slot: the echo, its state and spread, two scratch entries.
                         cfg.detector.seabed_capacity * 48.0 + 2.0 * cfg.detector.risen_capacity * 32.0 +
                         cfg.detector.replay_pings * 176.0 +
                         cfg.detector.replay_fls_frames * (static_cast<double>(cfg.fls.rows) * cfg.fls.beams + 192.0) +
                         cfg.survey.published_capacity * 48.0;
    return bytes > 1e18 ? static_cast<std::size_t>(1e18) : static_cast<std::size_t>(bytes);
}

namespace {
const MapperConfig& checked(const MapperConfig& cfg) {
    const std::string err = validateConfig(cfg);
    if (!err.empty()) throw std::invalid_argument("mapper config: " + err);
    return cfg;
}
std::vector<VoxelMap> makeMaps(const MapperConfig& cfg) {
    std::vector<VoxelMap> maps;
    maps.reserve(static_cast<std::size_t>(cfg.survey.max_maps));
    for (int i = 0; i < cfg.survey.max_maps; ++i) maps.emplace_back(cfg.map);
    return maps;
}
}  // namespace

Mapper::Mapper(const MapperConfig& cfg)
    : cfg_(checked(cfg)), maps_(makeMaps(cfg)), slots_(maps_.size()),
      release_margin_(cfg.survey.release_margin >= 0.0 ? cfg.survey.release_margin
                                                       : std::max(cfg.fls.range_max, cfg.ps.range_max)),
      published_(static_cast<std::size_t>(cfg.survey.published_capacity)), fls_model_(cfg.fls), ps_model_(cfg.ps),
      fls_updater_(fls_model_, cfg.update, maps_.front(), cfg.fls_max_geometries, flsMaxArcSamples(cfg, fls_model_)),
      ps_carver_(ps_model_, cfg.update),
      detector_(cfg.detector), segmenter_(cfg.segmentation, cfg.update.require_ps_observation, maps_.front()),
      nav_(cfg.nav_buffer_capacity, cfg.max_nav_gap_us) {
    finalised_.reserve(static_cast<std::size_t>(cfg.segmentation.max_objects));
    // The per-ping geometry slots, each with the configured sonar's capacity.
    fls_models_.reserve(static_cast<std::size_t>(cfg.fls_max_geometries - 1));
    for (int i = 1; i < cfg.fls_max_geometries; ++i) fls_models_.emplace_back(cfg.fls);
    fls_geometry_used_.assign(static_cast<std::size_t>(cfg.fls_max_geometries), 0);
    held_pings_.resize(static_cast<std::size_t>(cfg.detector.replay_pings));
    held_frames_.resize(static_cast<std::size_t>(cfg.detector.replay_fls_frames));
    held_pixels_.assign(held_frames_.size() * static_cast<std::size_t>(cfg.fls.rows) * cfg.fls.beams, 0);
}

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
            markLeftMaps(nav.pose.position);
            return count(Outcome::Used);
        }
    }
    nav_candidate_count_ = 0;  // the current timeline goes on: whatever was held was a glitch
    (void)nav_.add(nav);
    track_axis_.add(nav.pose.yaw);
    ++counters_.nav_used;
    markLeftMaps(nav.pose.position);
    return count(Outcome::Used);
}

// A map the vehicle is farther from, horizontally, than its extent plus the
// release margin can no longer be reached by either sonar: it is frozen from
// this NAV on (so when it is finalised does not change its contents).
void Mapper::markLeftMaps(const Eigen::Vector3d& vehicle) {
    for (std::size_t s = 0; s < maps_.size(); ++s) {
        if (!updatable(static_cast<int>(s))) continue;
        const VoxelMap& m = maps_[s];
        const Eigen::Vector2d lo = m.origin().head<2>(), hi = lo + m.extent().head<2>();
        const Eigen::Vector2d xy = vehicle.head<2>();
        const Eigen::Vector2d d = (lo - xy).cwiseMax(xy - hi).cwiseMax(Eigen::Vector2d::Zero());
        if (d.norm() > release_margin_) slots_[s].leaving = true;
    }
}

bool Mapper::reaches(int slot, const Eigen::Vector3d& p, double range) const {
    return maps_[static_cast<std::size_t>(slot)].distanceTo(p) <= range;
}

int Mapper::activeMaps() const {
    int n = 0;
    for (const MapSlot& s : slots_) n += s.inUse();
    return n;
}

void Mapper::onDetection(const Eigen::Vector3d& at) {
    ++counters_.detections;
    const Eigen::Vector2d xy = at.head<2>();
    auto inside = [&](std::size_t s) {
        const Eigen::Vector2d lo = maps_[s].origin().head<2>(), hi = lo + maps_[s].extent().head<2>();
        return (xy.array() >= lo.array()).all() && (xy.array() < hi.array()).all();
    };
    for (std::size_t s = 0; s < maps_.size(); ++s) {
        if (slots_[s].inUse() && inside(s)) {
            ++counters_.detection_in_active_map;
            return;
        }
    }
    // Inside a finalised map still kept (a later line over its area): reopen
    // it, so what this line sees is fused with what the earlier one saw; its
    // published boxes are retired, since it publishes its objects again.
    for (std::size_t s = 0; s < maps_.size(); ++s) {
        if (!slots_[s].parked || !inside(s)) continue;
        slots_[s].parked = false;
        slots_[s].leaving = false;
        for (int i = 0; i < published_count_; ++i) {
            Box& b = published_[static_cast<std::size_t>(i)];
            if (b.map_id == slots_[s].id) b = Box{Eigen::Vector3d::Constant(kRetiredBox), Eigen::Vector3d::Constant(-kRetiredBox), 0};
        }
        ++counters_.detection_reopened_map;
        return;
    }
    // On an object already published (a later line over it): mapping it again
    // would only publish it twice.
    const double r = cfg_.detector.cluster_radius;
    for (int i = 0; i < published_count_; ++i) {
        const Box& b = published_[static_cast<std::size_t>(i)];
        if ((xy.array() >= b.lo.head<2>().array() - r).all() && (xy.array() <= b.hi.head<2>().array() + r).all()) {
            ++counters_.detection_known_object;
            return;
        }
    }
    initialiseMapAt(at);
}

int Mapper::slotForNewMap() {
    int parked = -1;
    for (int s = 0; s < slotCount(); ++s) {
        const MapSlot& m = slots_[static_cast<std::size_t>(s)];
        if (m.id == 0) return s;
        if (m.parked && (parked < 0 || m.id < slots_[static_cast<std::size_t>(parked)].id)) parked = s;
    }
    if (parked >= 0) {
        maps_[static_cast<std::size_t>(parked)].release();
        slots_[static_cast<std::size_t>(parked)] = MapSlot{};
    }
    return parked;
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

Outcome Mapper::checkFlsGeometry(const FlsFrame& f) const {
    if (f.data == nullptr || f.rows < 2 || f.cols < 1 || f.rows > fls_model_.rowCapacity() ||
        f.cols > fls_model_.colCapacity() ||
        f.data_size != static_cast<std::size_t>(f.rows) * static_cast<std::size_t>(f.cols))
        return Outcome::FlsSizeMismatch;
    if (f.row_range == nullptr || f.beam_bearing == nullptr) return Outcome::FlsBadGeometry;
    // The aperture and the range window may be narrower than the configured
    // sonar's (a range setting, a zoom), never wider: the tables are sized for it.
    if (!(std::isfinite(f.elevation_min) && std::isfinite(f.elevation_max) && f.elevation_min < f.elevation_max &&
          f.elevation_min >= cfg_.fls.elevation_min - kFlsApertureTol &&
          f.elevation_max <= cfg_.fls.elevation_max + kFlsApertureTol))
        return Outcome::FlsBadGeometry;
    const double range_limit = fls_model_.rangeMax() + flsRangeTolerance(fls_model_);
    // Row 0 farthest: strictly decreasing ranges, finite, >= 0.
    if (!(std::isfinite(f.row_range[0]) && f.row_range[0] <= range_limit)) return Outcome::FlsBadGeometry;
    for (int r = 1; r < f.rows; ++r)
        if (!(std::isfinite(f.row_range[r]) && f.row_range[r] < f.row_range[r - 1])) return Outcome::FlsBadGeometry;
    if (!(f.row_range[f.rows - 1] >= 0.0f)) return Outcome::FlsBadGeometry;
    // Column 0 port-most: strictly increasing bearings, forward of the sonar.
    for (int c = 0; c < f.cols; ++c)
        if (!(std::isfinite(f.beam_bearing[c]) && std::fabs(f.beam_bearing[c]) <= 0.5 * M_PI &&
              (c == 0 || f.beam_bearing[c] > f.beam_bearing[c - 1])))
            return Outcome::FlsBadGeometry;
    return Outcome::Used;
}

int Mapper::flsGeometrySlot(const FlsFrame& frame) {
    const int slots = fls_updater_.geometries();
    int victim = -1;
    for (int i = 1; i < slots; ++i) {
        int64_t& used = fls_geometry_used_[static_cast<std::size_t>(i)];
        if (used != 0 && fls_models_[static_cast<std::size_t>(i) - 1].sameGeometry(frame)) {
            used = ++fls_geometry_tick_;
            return i;
        }
        // An empty slot first, else the least recently used.
        if (victim < 0 || used < fls_geometry_used_[static_cast<std::size_t>(victim)]) victim = i;
    }
    if (victim < 0) return -1;
    int64_t& used = fls_geometry_used_[static_cast<std::size_t>(victim)];
    if (used != 0) ++counters_.fls_geometry_evictions;
    used = 0;
    FlsModel& model = fls_models_[static_cast<std::size_t>(victim) - 1];
    if (!model.assign(frame) || !fls_updater_.bind(victim, model)) return -2;
    ++counters_.fls_geometry_builds;
    used = ++fls_geometry_tick_;
    return victim;
}

Outcome Mapper::addFls(const FlsFrame& frame) {
    ++counters_.fls_in;
    if (frame.hasGeometry()) {
        if (Outcome o = checkFlsGeometry(frame); o != Outcome::Used) return count(o);
    } else if (!fls_model_.frameMatches(frame)) {
        return count(Outcome::FlsSizeMismatch);
    }
    if (!cfg_.update.fls_enabled) return count(Outcome::FlsDisabled);
    Pose pose;
    if (Outcome o = lookupPose(frame.utime, pose); o != Outcome::Used) return count(o);
    const Eigen::Isometry3d world_from_sensor = sensorToWorld(pose, cfg_.fls_mount);
    bool any = false;
    for (int s = 0; s < slotCount() && !any; ++s) any = updatable(s);
    const bool detect = cfg_.detector.fls_nearer_than_seabed || cfg_.detector.fls_shadow_false_alarm > 0.0;
    if (!any && !detect && held_frames_.empty()) return count(Outcome::FlsBeforeMap);
    // The frame's geometry: the configured one (no geometry given, or the same),
    // else a cached one (tables computed once per geometry, LRU).
    int geometry = 0;
    double range_max = cfg_.fls.range_max;
    if (frame.hasGeometry() && !fls_model_.sameGeometry(frame)) {
        geometry = flsGeometrySlot(frame);
        if (geometry == -1) return count(any ? Outcome::FlsGeometryNotCached : Outcome::FlsBeforeMap);
        if (geometry < 0) return count(any ? Outcome::FlsBadGeometry : Outcome::FlsBeforeMap);
        range_max = fls_models_[static_cast<std::size_t>(geometry) - 1].rangeMax();
    }
    const FlsModel& model = flsGeometryModel(geometry);
    // DetectorConfig::replay_fls_frames: frames of the configured geometry are
    // held for a map anchored later (this frame included).
    const bool hold = !held_frames_.empty() && geometry == 0;
    // The detector's plane where the FLS boresight meets the seabed: the seabed
    // the votes are judged against (UpdateConfig::fls_seabed_at_footprint; the
    // plane's gradient carries it across the fan) and the detector's own.
    const Eigen::Vector3d boresight = flsBoresight(model, world_from_sensor);
    // Fitted only where something uses it (two fits per frame).
    const std::optional<SeabedFit> footprint =
        detect || ((any || hold) && cfg_.update.fls_seabed_at_footprint)
            ? detector_.seabedAlongRay(world_from_sensor.translation(), boresight)
            : std::nullopt;
    const std::optional<SeabedFit>& vote_seabed =
        cfg_.update.fls_seabed_at_footprint ? footprint : detector_.seabedAtNewestEcho();
    last_fls_seabed_ = vote_seabed;
    // Held frames that waited for a seabed plane (fls_seabed_judged_later):
    // before this frame is held, which may take the oldest's place.
    if (awaiting_frames_ > 0 && vote_seabed) judgeAwaitingFrames(kAwaitingJudgedPerFrame);
    if (hold) holdFrame(frame, world_from_sensor, vote_seabed);
    if (any) {
        fls_updater_.select(geometry);
        fls_updater_.setSeabed(vote_seabed);
        for (int s = 0; s < slotCount(); ++s) {
            if (!updatable(s)) continue;
            if (!reaches(s, world_from_sensor.translation(), range_max)) continue;
            if (hold && !vote_seabed && judgesLater()) {
                const int cap = static_cast<int>(held_frames_.size());
                awaitSeabed(held_frames_[static_cast<std::size_t>((held_frame_next_ - 1 + cap) % cap)], s);
            }
            const FlsUpdateStats st = fls_updater_.apply(frame, world_from_sensor, maps_[static_cast<std::size_t>(s)]);
            counters_.fls_points_outside_map += st.points_outside_map;
            if (st.points_in_map > 0) ++slots_[static_cast<std::size_t>(s)].updates;
        }
    }
    // The FLS's evidence for the detector (DetectorConfig::fls_nearer_than_seabed,
    // fls_shadow_false_alarm): after the maps, so a map this frame anchors
    // starts with the next one (as for the PS).
    if (detect && footprint) {
        const double margin = 3.0 * footprint->rms + 0.5 * cfg_.map.resolution;
        if (cfg_.detector.fls_nearer_than_seabed) {
            const std::optional<Eigen::Vector3d> risen = flsReturnNearerThanSeabed(
                frame, model, world_from_sensor, *footprint, cfg_.update.fls_intensity_threshold, margin);
            if (risen && detector_.addRisenEcho(*risen)) onDetection(*detector_.detection());
        }
        // DetectorConfig::fls_shadow_false_alarm: dark as the FLS's free space
        // judges it (UpdateConfig::fls_free_space_noise_sigmas).
        if (cfg_.detector.fls_shadow_false_alarm > 0.0) {
            const std::optional<Eigen::Vector3d> shadow =
                flsShadowOnSeabed(frame, model, world_from_sensor, *footprint, margin,
                                  noiseLevel(frame, cfg_.update.fls_free_space_noise_sigmas),
                                  cfg_.detector.fls_shadow_false_alarm, cfg_.detector.fls_shadow_like_water);
            if (shadow) ++counters_.fls_shadows;
            if (shadow && detector_.addShadow(*shadow)) onDetection(*detector_.detection());
        }
    }
    if (!any) return count(Outcome::FlsBeforeMap);
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

    // Paper 2.3: closest-group range, then carving (Eqs. 10-13), into every
    // map being made. Carving first: a map the detector anchors on this ping
    // starts with the next one.
    bool any = false;
    for (int s = 0; s < slotCount(); ++s) any = any || updatable(s);
    const bool hold = !held_pings_.empty() && cfg_.update.ps_carving_enabled;
    std::optional<PsEchoGroup> group;
    double carve_range = -1.0;
    if (any || hold) {
        group = closestGroup(ping, cfg_.ps_selection);
        // Carving stops at the first bin that could be an echo (UpdateConfig::ps_carve_noise_sigmas,
        // ps_carve_echo_window_voxels).
        if (group)
            carve_range = carveStopRange(ping, *group, cfg_.ps_selection, cfg_.update.ps_carve_noise_sigmas,
                                         cfg_.update.ps_carve_echo_window_voxels * cfg_.map.resolution);
    }
    if (hold && group) {
        // Held for a map anchored later (replayHeldPings), this ping included.
        held_pings_[static_cast<std::size_t>(held_next_)] =
            HeldPing{world_from_sensor, ping.head_angle, rangeOfBin(ping, group->peak), ping.intensity[group->peak] / 255.0,
                     carve_range, ping.range_max};
        held_next_ = (held_next_ + 1) % static_cast<int>(held_pings_.size());
        held_count_ = std::min(held_count_ + 1, static_cast<int>(held_pings_.size()));
    }
    for (int s = 0; s < slotCount(); ++s) {
        if (!updatable(s)) continue;
        if (!group || !cfg_.update.ps_carving_enabled) continue;
        if (!reaches(s, world_from_sensor.translation(), ping.range_max)) continue;
        const PsCarveStats st = ps_carver_.apply(ping.head_angle, rangeOfBin(ping, group->peak), world_from_sensor,
                                                 maps_[static_cast<std::size_t>(s)], ping.intensity[group->peak] / 255.0,
                                                 carve_range);
        counters_.ps_endpoints_outside_map += st.endpoints_outside_map;
        if (st.endpoints_in_map > 0) ++slots_[static_cast<std::size_t>(s)].updates;
    }

    // Paper 2.1: the strongest echo of the ping feeds the rising-edge detector,
    // which stays armed for the next object (survey mode).
    const std::optional<int> peak = maxIntensityBin(ping, cfg_.ps_selection);
    // DetectorConfig::nearest_echo_sigmas: the ping's nearest echo, when nearer than its strongest.
    const int nearest_bin = cfg_.detector.nearest_echo_sigmas > 0.0
                                ? firstEchoBin(ping, cfg_.ps_selection, cfg_.detector.nearest_echo_sigmas)
                                : -1;
    const bool nearer = nearest_bin >= 0 && (!peak || nearest_bin < *peak);
    auto pointAt = [&](int bin, double head) {
        return world_from_sensor * (rangeOfBin(ping, bin) * ps_model_.centreDirection(head));
    };
    // The nearest echo goes on the fan's steepest edge: a level seabed returns
    // first from there, so its own leading edge does not rise.
    const double steepest = ping.head_angle + 0.5 * cfg_.ps.beam_width_vertical;
    bool declared = false;
    if (peak) {
        // DetectorConfig::rise_from_deepest_in_beam: the strongest echo may have
        // come from anywhere across the fan's thickness, as deep as its steepest edge.
        const FanEcho e = fanEcho(world_from_sensor, rangeOfBin(ping, *peak), ping.head_angle);
        declared = nearer ? detector_.addEchoPoint(e.at, pointAt(nearest_bin, steepest), e.deeper_by)
                          : detector_.addEchoPoint(e.at, e.deeper_by);
    }
    else if (nearer)
        declared = detector_.addNearestEcho(pointAt(nearest_bin, steepest));
    if (declared) onDetection(*detector_.detection());
    if (any ? !group : !peak) return count(Outcome::PsNoEcho);
    ++counters_.ps_used;
    return count(Outcome::Used);
}

const SegmentationStats& Mapper::segment() { return segmentSlot(0); }

const SegmentationStats& Mapper::segmentSlot(int slot) {
    segmenter_.setAlongTrack(track_axis_.axis());
    return segmenter_.run(maps_[static_cast<std::size_t>(slot)]);
}

int Mapper::leavingSlot() const {
    int best = -1;
    for (int s = 0; s < slotCount(); ++s) {
        const MapSlot& m = slots_[static_cast<std::size_t>(s)];
        if (m.inUse() && m.leaving && (best < 0 || m.id < slots_[static_cast<std::size_t>(best)].id)) best = s;
    }
    return best;
}

void Mapper::leaveAll() {
    for (MapSlot& s : slots_)
        if (s.inUse()) s.leaving = true;
}

const std::vector<ObjectInfo>& Mapper::finaliseSlot(int slot) {
    finalised_.clear();
    const VoxelMap& own = maps_[static_cast<std::size_t>(slot)];
    (void)segmentSlot(slot);
    const float occupied = static_cast<float>(logOddsFromProbability(cfg_.segmentation.occupied_probability));
    // Occupied voxels of map `m` whose centres lie inside the box.
    auto occupiedIn = [&](const VoxelMap& m, const ObjectInfo& o) {
        const double res = m.resolution();
        VoxelIndex lo, hi;
        lo.x = std::max(0, static_cast<int>(std::ceil((o.bbox_min.x() - m.origin().x()) / res - 0.5)));
        lo.y = std::max(0, static_cast<int>(std::ceil((o.bbox_min.y() - m.origin().y()) / res - 0.5)));
        lo.z = std::max(0, static_cast<int>(std::ceil((o.bbox_min.z() - m.origin().z()) / res - 0.5)));
        hi.x = std::min(m.nx() - 1, static_cast<int>(std::floor((o.bbox_max.x() - m.origin().x()) / res - 0.5)));
        hi.y = std::min(m.ny() - 1, static_cast<int>(std::floor((o.bbox_max.y() - m.origin().y()) / res - 0.5)));
        hi.z = std::min(m.nz() - 1, static_cast<int>(std::floor((o.bbox_max.z() - m.origin().z()) / res - 0.5)));
        int n = 0;
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) n += m.logOdds(m.linear({x, y, z})) > occupied;
        return n;
    };
    for (const ObjectInfo& o : segmenter_.objects()) {
        // An object at this map's edge that another map still being made sees
        // more of is left to that map (it publishes it when it is finalised).
        bool other = false;
        const int own_count = occupiedIn(own, o);
        for (int s = 0; s < slotCount() && !other; ++s)
            if (s != slot && slots_[static_cast<std::size_t>(s)].inUse() &&
                occupiedIn(maps_[static_cast<std::size_t>(s)], o) > own_count)
                other = true;
        if (other) {
            ++counters_.objects_left_to_other_map;
            continue;
        }
        bool duplicate = false;
        for (int i = 0; i < published_count_ && !duplicate; ++i) {
            const Box& b = published_[static_cast<std::size_t>(i)];
            duplicate = (o.bbox_min.array() < b.hi.array()).all() && (b.lo.array() < o.bbox_max.array()).all();
        }
        if (duplicate) {
            ++counters_.objects_duplicate;
            continue;
        }
        published_[static_cast<std::size_t>(published_next_)] = Box{o.bbox_min, o.bbox_max, slots_[static_cast<std::size_t>(slot)].id};
        published_next_ = (published_next_ + 1) % static_cast<int>(published_.size());
        published_count_ = std::min(published_count_ + 1, static_cast<int>(published_.size()));
        finalised_.push_back(o);
        ++counters_.objects_published;
    }
    ++counters_.maps_finalised;
    return finalised_;
}

void Mapper::releaseSlot(int slot) {
    MapSlot& m = slots_[static_cast<std::size_t>(slot)];
    if (cfg_.survey.reopen_on_revisit && m.id != 0) {
        m.parked = true;
        m.leaving = false;
        return;
    }
    maps_[static_cast<std::size_t>(slot)].release();
    m = MapSlot{};
}

void Mapper::initialiseMapAt(const Eigen::Vector3d& centre) {
    // The first free slot (slot 0 in a fresh mapper: map()), else the oldest parked one.
    const int s = slotForNewMap();
    if (s < 0) {
        ++counters_.detection_no_free_map;  // never evicts a map still being made
        return;
    }
    slots_[static_cast<std::size_t>(s)] = MapSlot{next_map_id_++, false, 0, false};
    maps_[static_cast<std::size_t>(s)].initialiseAt(centre);
    ++counters_.map_initialisations;
    replayHeldPings(s);
    replayHeldFrames(s);
}

void Mapper::holdFrame(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor,
                       const std::optional<SeabedFit>& seabed) {
    const std::size_t pixels = held_pixels_.size() / held_frames_.size();
    if (frame.data_size != pixels) return;  // the configured geometry only
    std::copy(frame.data, frame.data + pixels, held_pixels_.begin() + static_cast<std::ptrdiff_t>(held_frame_next_ * pixels));
    HeldFrame& h = held_frames_[static_cast<std::size_t>(held_frame_next_)];
    if (h.awaiting_map != 0) --awaiting_frames_;  // never found a plane: its looks are lost
    h = HeldFrame{frame.utime, world_from_sensor, seabed, 0};
    const int cap = static_cast<int>(held_frames_.size());
    held_frame_next_ = (held_frame_next_ + 1) % cap;
    held_frame_count_ = std::min(held_frame_count_ + 1, cap);
}

// The FLS boresight (the middle of the fan and of the elevation arc) in the world frame.
Eigen::Vector3d Mapper::flsBoresight(const FlsModel& model, const Eigen::Isometry3d& world_from_sensor) {
    const int right = model.cols() / 2, left = std::max(0, model.cols() - 1 - right);
    return world_from_sensor.linear() *
           (model.edgeDirection(left, 1) + model.edgeDirection(right, 1)).cast<double>().normalized();
}

// DetectorConfig::replay_fls_frames: the FLS looks at an object before the
// detector declared it are applied to its new map as they would have been had
// the map existed, in their order, each judged against the seabed it was then.
// UpdateConfig::fls_seabed_judged_later: one judged with no plane is judged
// against the plane found at its footprint since, or waits for one
// (judgeAwaitingFrames).
void Mapper::replayHeldFrames(int slot) {
    const int cap = static_cast<int>(held_frames_.size());
    if (cap == 0 || held_frame_count_ == 0) return;
    const std::size_t pixels = held_pixels_.size() / held_frames_.size();
    fls_updater_.select(0);
    for (int k = 0; k < held_frame_count_; ++k) {
        const int i = (held_frame_next_ - held_frame_count_ + k + cap) % cap;
        HeldFrame& h = held_frames_[static_cast<std::size_t>(i)];
        if (!reaches(slot, h.world_from_sensor.translation(), cfg_.fls.range_max)) continue;
        std::optional<SeabedFit> seabed = h.seabed;
        if (!seabed && judgesLater()) {
            seabed = detector_.seabedAlongRay(h.world_from_sensor.translation(), flsBoresight(fls_model_, h.world_from_sensor));
            if (seabed) {
                ++counters_.fls_frames_judged_later;
            } else {
                awaitSeabed(h, slot);
            }
        }
        FlsFrame f = heldFrameImage(i, pixels);
        fls_updater_.setSeabed(seabed);
        const FlsUpdateStats st = fls_updater_.apply(f, h.world_from_sensor, maps_[static_cast<std::size_t>(slot)]);
        counters_.fls_points_outside_map += st.points_outside_map;
        if (st.points_in_map > 0) ++slots_[static_cast<std::size_t>(slot)].updates;
        ++counters_.fls_frames_replayed;
    }
}

FlsFrame Mapper::heldFrameImage(int index, std::size_t pixels) const {
    FlsFrame f;
    f.utime = held_frames_[static_cast<std::size_t>(index)].utime;
    f.rows = fls_model_.rows();
    f.cols = fls_model_.cols();
    f.data = held_pixels_.data() + static_cast<std::size_t>(index) * pixels;
    f.data_size = pixels;
    return f;
}

void Mapper::awaitSeabed(HeldFrame& h, int slot) {
    if (h.awaiting_map != 0) return;  // one map per frame: the first it was applied to
    h.awaiting_map = slots_[static_cast<std::size_t>(slot)].id;
    ++awaiting_frames_;
}

// Only the above-seabed votes of a frame already applied with no seabed plane
// (FlsUpdater::applyAboveSeabedVotes makes no other call).
class AboveSeabedOnlySink {
public:
    explicit AboveSeabedOnlySink(VoxelMap& map) : out_(map.writer()) {}
    void aboveSeabed(std::size_t v) { out_.addAboveSeabedVote(v); }

private:
    VoxelMap::Writer out_;
};

// UpdateConfig::fls_seabed_judged_later: the held frames applied while no
// seabed plane existed at their footprint, oldest first, judged against the
// one there now, at most `budget` of them; those still without one wait on
// (until the ring reuses them).
void Mapper::judgeAwaitingFrames(int budget) {
    const int cap = static_cast<int>(held_frames_.size());
    const std::size_t pixels = held_pixels_.size() / held_frames_.size();
    fls_updater_.select(0);
    for (int k = 0; k < held_frame_count_ && awaiting_frames_ > 0 && budget > 0; ++k) {
        const int i = (held_frame_next_ - held_frame_count_ + k + cap) % cap;
        HeldFrame& h = held_frames_[static_cast<std::size_t>(i)];
        if (h.awaiting_map == 0) continue;
        int slot = -1;
        for (int s = 0; s < slotCount(); ++s)
            if (slots_[static_cast<std::size_t>(s)].id == h.awaiting_map && updatable(s)) slot = s;
        if (slot >= 0) {
            const std::optional<SeabedFit> seabed =
                detector_.seabedAlongRay(h.world_from_sensor.translation(), flsBoresight(fls_model_, h.world_from_sensor));
            if (!seabed) continue;
            fls_updater_.setSeabed(seabed);
            AboveSeabedOnlySink sink(maps_[static_cast<std::size_t>(slot)]);
            (void)fls_updater_.applyAboveSeabedVotes(heldFrameImage(i, pixels), h.world_from_sensor,
                                                      maps_[static_cast<std::size_t>(slot)], sink);
            ++counters_.fls_frames_judged_later;
            --budget;
        }
        h.awaiting_map = 0;  // judged, or its map is gone
        --awaiting_frames_;
    }
}

void Mapper::saveHeldFrames(StateWriter& w) const {
    const std::size_t pixels = held_frames_.empty() ? 0 : held_pixels_.size() / held_frames_.size();
    w.pod(held_frame_count_);
    w.pod(held_frame_next_);
    for (int i = 0; i < held_frame_count_; ++i) {
        const HeldFrame& h = held_frames_[static_cast<std::size_t>(i)];
        w.pod(h.utime);
        const Eigen::Matrix<double, 3, 4> m = h.world_from_sensor.matrix().topRows<3>();
        for (int k = 0; k < 12; ++k) w.pod(m.data()[k]);
        w.pod(static_cast<uint8_t>(h.seabed.has_value()));
        const SeabedFit f = h.seabed.value_or(SeabedFit{});
        for (double v : {f.centre.x(), f.centre.y(), f.depth, f.gradient.x(), f.gradient.y(), f.rms}) w.pod(v);
        w.pod(f.echoes);
        w.pod(h.awaiting_map);
        w.bytes(held_pixels_.data() + static_cast<std::size_t>(i) * pixels, pixels);
    }
}

bool Mapper::loadHeldFrames(StateReader& r) {
    const int cap = static_cast<int>(held_frames_.size());
    if (!r.pod(held_frame_count_) || !r.pod(held_frame_next_) || held_frame_count_ < 0 || held_frame_count_ > cap ||
        held_frame_next_ < 0 || held_frame_next_ >= std::max(cap, 1) ||
        (held_frame_count_ < cap && held_frame_next_ != held_frame_count_ % std::max(cap, 1)))
        return false;
    awaiting_frames_ = 0;
    const std::size_t pixels = held_frames_.empty() ? 0 : held_pixels_.size() / held_frames_.size();
    for (int i = 0; i < held_frame_count_; ++i) {
        HeldFrame& h = held_frames_[static_cast<std::size_t>(i)];
        Eigen::Matrix<double, 3, 4> m;
        uint8_t has = 0;
        SeabedFit f;
        if (!r.pod(h.utime)) return false;
        for (int k = 0; k < 12; ++k)
            if (!r.pod(m.data()[k])) return false;
        if (!r.pod(has) || has > 1) return false;
        for (double* v : {&f.centre.x(), &f.centre.y(), &f.depth, &f.gradient.x(), &f.gradient.y(), &f.rms})
            if (!r.pod(*v) || !std::isfinite(*v)) return false;
        if (!r.pod(f.echoes) || !r.pod(h.awaiting_map) || h.awaiting_map < 0 || !m.allFinite() ||
            !r.bytes(held_pixels_.data() + static_cast<std::size_t>(i) * pixels, pixels))
            return false;
        if (h.awaiting_map != 0) ++awaiting_frames_;
        h.world_from_sensor.matrix().topRows<3>() = m;
        h.world_from_sensor.matrix().row(3) << 0.0, 0.0, 0.0, 1.0;
        h.seabed.reset();
        if (has) h.seabed = f;
    }
    return true;
}

Mapper::FanEcho Mapper::fanEcho(const Eigen::Isometry3d& world_from_sensor, double range, double head) const {
    const Eigen::Vector3d at = world_from_sensor * (range * ps_model_.centreDirection(head));
    const Eigen::Vector3d deepest =
        world_from_sensor * (range * ps_model_.centreDirection(head + 0.5 * cfg_.ps.beam_width_vertical));
    return {at, deepest.z() - at.z()};
}

bool Mapper::psSectorHasPassed(const Eigen::Vector3d& object) const {
    if (held_count_ == 0) return false;
    const int cap = static_cast<int>(held_pings_.size());
    const HeldPing& newest = held_pings_[static_cast<std::size_t>((held_next_ - 1 + cap) % cap)];
    const Eigen::Vector3d sensor = newest.world_from_sensor.translation();
    const Eigen::Vector3d echo = newest.world_from_sensor * (newest.range * ps_model_.centreDirection(newest.head_angle));
    const Eigen::Vector2d look = (echo - sensor).head<2>();
    const double below = object.z() - sensor.z();  // NED: how far the object lies under the sensor
    if (look.norm() < 1e-6 || !(below > 0.0)) return false;
    // The sector's steepest ray (the head's far limit, plus half the fan's thickness).
    const double steepest = std::min(std::max(std::fabs(cfg_.ps.tilt + cfg_.ps.head_min), std::fabs(cfg_.ps.tilt + cfg_.ps.head_max)) +
                                         0.5 * cfg_.ps.beam_width_vertical,
                                     0.5 * M_PI - 1e-6);
    const double near_edge = below / std::tan(steepest);
    const double ahead = look.normalized().dot((object - sensor).head<2>());
    return ahead < near_edge + cfg_.detector.cluster_radius;
}

// The detector declares an object only once enough risen echoes gather, and
// only once a seabed plane exists where they lie (ObjectDetector): by then the
// PS may have swept past the object (a mission starting close to it, a vehicle
// fast for its ping rate). The pings that found it are carved into the new map
// in their order, the ping that declared it the newest of them: as water only
// (DetectorConfig::replay_pings_carve_only, CarvingOnlySink), or as they would
// have been had the map existed; with carving only, the risen ones whole when
// early echoes declared the map and the PS sector has passed the object
// (DetectorConfig::replay_risen_pings_whole).
void Mapper::replayHeldPings(int slot) {
    const bool early = cfg_.detector.replay_risen_pings_whole && detector_.declaredByEarlyEchoes() &&
                       psSectorHasPassed(*detector_.detection());
    const int n = held_count_;
    const int cap = static_cast<int>(held_pings_.size());
    for (int k = 0; k < n; ++k) {
        const HeldPing& h = held_pings_[static_cast<std::size_t>((held_next_ - n + k + cap) % cap)];
        if (!reaches(slot, h.world_from_sensor.translation(), h.range_max)) continue;
        VoxelMap& map = maps_[static_cast<std::size_t>(slot)];
        PsCarveStats st;
        // DetectorConfig::replay_risen_pings_whole: when echoes taken before any
        // seabed plane declared the map, the PS has looked at the object only
        // before it existed; a held ping whose echo rises is such a look,
        // replayed as a live ping.
        const bool whole = early && [&] {
            const FanEcho e = fanEcho(h.world_from_sensor, h.range, h.head_angle);
            return detector_.heldEchoRises(e.at, e.deeper_by);
        }();
        if (cfg_.detector.replay_pings_carve_only && !whole) {
            MapWriterSink out(map);
            CarvingOnlySink<MapWriterSink> sink(out);
            st = ps_carver_.apply(h.head_angle, h.range, h.world_from_sensor, map, sink, h.strength, h.carve_range);
        } else {
            st = ps_carver_.apply(h.head_angle, h.range, h.world_from_sensor, map, h.strength, h.carve_range);
        }
        counters_.ps_endpoints_outside_map += st.endpoints_outside_map;
        if (st.endpoints_in_map > 0) ++slots_[static_cast<std::size_t>(slot)].updates;
        ++counters_.ps_pings_replayed;
    }
}


void Mapper::saveState(StateWriter& w) const {
    w.pod(static_cast<uint64_t>(maps_.size()));
    for (std::size_t s = 0; s < maps_.size(); ++s) {
        maps_[s].saveState(w);
        w.pod(slots_[s].id);
        w.pod(static_cast<uint8_t>(slots_[s].leaving));
        w.pod(slots_[s].updates);
        w.pod(static_cast<uint8_t>(slots_[s].parked));
    }
    w.pod(next_map_id_);
    w.pod(published_count_);
    w.pod(published_next_);
    for (int i = 0; i < published_count_; ++i) {
        for (const Eigen::Vector3d* v : {&published_[static_cast<std::size_t>(i)].lo, &published_[static_cast<std::size_t>(i)].hi})
            for (int k = 0; k < 3; ++k) w.pod((*v)[k]);
        w.pod(published_[static_cast<std::size_t>(i)].map_id);
    }
    detector_.saveState(w);
    w.pod(held_count_);
    w.pod(held_next_);
    for (int i = 0; i < held_count_; ++i) {
        const HeldPing& h = held_pings_[static_cast<std::size_t>(i)];
        const Eigen::Matrix<double, 3, 4> m = h.world_from_sensor.matrix().topRows<3>();
        for (int k = 0; k < 12; ++k) w.pod(m.data()[k]);
        for (double v : {h.head_angle, h.range, h.strength, h.carve_range, h.range_max}) w.pod(v);
    }
    saveHeldFrames(w);
    nav_.saveState(w);
    w.pod(nav_candidate_count_);
    for (int i = 0; i < nav_candidate_count_; ++i) saveTimedPose(w, nav_candidate_[i]);
    track_axis_.saveState(w);
    w.pod(counters_);
}

bool Mapper::loadState(StateReader& r) {
    int held = 0;
    if (!r.expect(static_cast<uint64_t>(maps_.size()))) return false;
    for (std::size_t s = 0; s < maps_.size(); ++s) {
        uint8_t leaving = 0, parked = 0;
        MapSlot m;
        if (!maps_[s].loadState(r) || !r.pod(m.id) || !r.pod(leaving) || !r.pod(m.updates) || !r.pod(parked) ||
            m.id < 0 || leaving > 1 || parked > 1 || (parked == 1 && (m.id == 0 || leaving == 1)) || m.updates < 0 ||
            (m.id != 0) != maps_[s].initialised())
            return false;
        m.leaving = leaving != 0;
        m.parked = parked != 0;
        slots_[s] = m;
    }
    const int cap = static_cast<int>(published_.size());
    if (!r.pod(next_map_id_) || next_map_id_ < 1 || !r.pod(published_count_) || !r.pod(published_next_) ||
        published_count_ < 0 || published_count_ > cap || published_next_ < 0 || published_next_ >= cap)
        return false;
    for (int i = 0; i < published_count_; ++i) {
        for (Eigen::Vector3d* v : {&published_[static_cast<std::size_t>(i)].lo, &published_[static_cast<std::size_t>(i)].hi})
            for (int k = 0; k < 3; ++k)
                if (!r.pod((*v)[k]) || !std::isfinite((*v)[k])) return false;
        if (!r.pod(published_[static_cast<std::size_t>(i)].map_id) || published_[static_cast<std::size_t>(i)].map_id < 0)
            return false;
    }
    if (!detector_.loadState(r) || !loadHeldPings(r) || !loadHeldFrames(r) || !nav_.loadState(r) || !r.pod(held) || held < 0 ||
        held >= cfg_.nav_timeline_confirm)
        return false;
    for (int i = 0; i < held; ++i)
        if (!loadTimedPose(r, nav_candidate_[i])) return false;
    nav_candidate_count_ = held;
    return track_axis_.loadState(r) && r.pod(counters_);
}

bool Mapper::loadHeldPings(StateReader& r) {
    const int cap = static_cast<int>(held_pings_.size());
    if (!r.pod(held_count_) || !r.pod(held_next_) || held_count_ < 0 || held_count_ > cap || held_next_ < 0 ||
        held_next_ >= std::max(cap, 1) || (held_count_ < cap && held_next_ != held_count_ % std::max(cap, 1)))
        return false;
    for (int i = 0; i < held_count_; ++i) {
        HeldPing& h = held_pings_[static_cast<std::size_t>(i)];
        Eigen::Matrix<double, 3, 4> m;
        for (int k = 0; k < 12; ++k)
            if (!r.pod(m.data()[k])) return false;
        for (double* v : {&h.head_angle, &h.range, &h.strength, &h.carve_range, &h.range_max})
            if (!r.pod(*v)) return false;
        if (!m.allFinite() || !std::isfinite(h.head_angle + h.range + h.strength + h.carve_range + h.range_max))
            return false;
        h.world_from_sensor.matrix().topRows<3>() = m;
        h.world_from_sensor.matrix().row(3) << 0.0, 0.0, 0.0, 1.0;
    }
    return true;
}

std::size_t Mapper::stateBytesBound() const {
    const std::size_t pose = sizeof(int64_t) + 6 * sizeof(double);
    // Per voxel: log-odds, flags, above-seabed votes, PS crossings.
    return 64 + maps_.size() * (maps_.front().size() * (sizeof(float) + 3) + 64) + 64 +
           published_.size() * 56 + 24 * 2 +
           static_cast<std::size_t>(cfg_.detector.seabed_capacity + 2 * cfg_.detector.risen_capacity) * 24 + 16 +
           held_frames_.size() * (8 + 12 * sizeof(double) + 1 + 6 * sizeof(double) + sizeof(int)) + held_pixels_.size() +
           16 +
           static_cast<std::size_t>(cfg_.detector.seabed_capacity) * (1 + sizeof(double)) + 64 + held_pings_.size() * 17 * sizeof(double) + 16 + 64 +
           static_cast<std::size_t>(cfg_.nav_buffer_capacity) * pose + 16 +
           static_cast<std::size_t>(kMaxNavTimelineConfirm) * pose + 64 + sizeof(MapperCounters);
}

}  // namespace sonarfusion
