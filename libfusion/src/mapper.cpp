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

// One validator: each struct's own validate() (config.hpp, src/config.cpp).
std::string validateConfig(const MapperConfig& cfg) {
    const std::optional<ConfigIssue> issue = cfg.validate();
    return issue ? issue->message() : std::string();
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
