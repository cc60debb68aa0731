#include "mapper_node.hpp"

#include "sonar_order.hpp"

#include <algorithm>
#include <cmath>
#include <spdlog/spdlog.h>

#include "message_convert.hpp"
#include "message_guard.hpp"
#include "sonarfusion/variant.hpp"

namespace sonarfusion {

namespace {
enum Channel { kNav = 0, kFls = 1, kPs = 2 };
constexpr int kTimingRing = 8192;
const char* kTransportNames[] = {"malformed",       "fls_geometry_mismatch", "stale",          "pending_overflow",
                                 "ps_geometry_mismatch", "bad_fingerprint", "truncated",   "trailing_bytes",
                                 "bad_count",       "duplicate"};
static_assert(sizeof(kTransportNames) / sizeof(kTransportNames[0]) == static_cast<int>(TransportReject::kCount));

int64_t wallUs() {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}
// The waiting message with the smallest (utime, seq), or null.
template <class P>
P* oldestPending(std::vector<P>& slots, int64_t before_epoch) {
    P* best = nullptr;
    for (P& p : slots)
        if (p.used && p.nav_epoch < before_epoch &&
            (!best || p.msg.utime < best->msg.utime || (p.msg.utime == best->msg.utime && p.msg.seq < best->msg.seq)))
            best = &p;
    return best;
}
template <class P>
bool earlier(const P& a, const P& b) {
    return a.msg.utime < b.msg.utime || (a.msg.utime == b.msg.utime && a.msg.seq < b.msg.seq);
}
// All slots are taken: free the one whose removal leaves the smallest time gap
// between its neighbours (never the oldest or the newest), so the waiting set
// stays spread over the time NAV is late and the map degrades gradually.
template <class P>
void thinOne(std::vector<P>& slots) {
    P* victim = nullptr;
    uint64_t best_gap = UINT64_MAX;
    for (P& p : slots) {
        if (!p.used) continue;
        const P *prev = nullptr, *next = nullptr;
        for (const P& q : slots) {
            if (!q.used || &q == &p) continue;
            if (earlier(q, p) && (!prev || earlier(*prev, q))) prev = &q;
            if (earlier(p, q) && (!next || earlier(q, *next))) next = &q;
        }
        if (!prev || !next) continue;
        const uint64_t gap = static_cast<uint64_t>(next->msg.utime) - static_cast<uint64_t>(prev->msg.utime);
        if (gap < best_gap) best_gap = gap, victim = &p;
    }
    if (!victim)  // fewer than three waiting: drop the oldest
        for (P& p : slots)
            if (p.used && (!victim || earlier(p, *victim))) victim = &p;
    victim->used = false;
}
bool near(double a, double b, double tol) { return std::fabs(a - b) <= tol; }
}  // namespace

MapperNode::MapperNode(const DaemonConfig& cfg, Publisher out)
    : cfg_(cfg), out_(std::move(out)), mapper_(cfg.mapper), variant_(cfg.variant) {
    // Pre-size every decoded message so decode() reuses capacity instead of allocating.
    const MapperConfig& m = cfg.mapper;
    limits_ = guard::limitsFor(m);
    // One slot more than configured: a message is always decoded into a free
    // slot, then the set is thinned if that took the last one.
    fls_pending_.resize(static_cast<std::size_t>(cfg.fls_pending_slots) + 1);
    for (auto& p : fls_pending_) {
        p.msg.beam_bearing.reserve(m.fls.beams);
        p.msg.row_range.reserve(m.fls.rows);
        p.msg.data.reserve(static_cast<std::size_t>(m.fls.rows) * m.fls.beams);
        p.msg.sensor_name.reserve(64);
    }
    ps_pending_.resize(static_cast<std::size_t>(cfg.ps_pending_slots) + 1);
    for (auto& p : ps_pending_) {
        p.msg.intensity.reserve(m.ps.bins);
        p.msg.sensor_name.reserve(64);
    }
    proc_us_.assign(kTimingRing, 0.0);
    scratch_.assign(kTimingRing, 0.0);

    for (int i = 1; i < kOutcomeCount; ++i) status_msg_.reason_name.emplace_back(outcomeName(static_cast<Outcome>(i)));
    for (const char* n : kTransportNames) status_msg_.reason_name.emplace_back(n);
    status_msg_.num_reasons = static_cast<int32_t>(status_msg_.reason_name.size());
    status_msg_.reason_count.assign(status_msg_.reason_name.size(), 0);
    status_msg_.variant = variant_;
    status_msg_.state.reserve(16);
    const std::size_t maps = static_cast<std::size_t>(m.survey.max_maps);
    status_msg_.map_ids.reserve(maps);
    status_msg_.map_centre_north.reserve(maps);
    status_msg_.map_centre_east.reserve(maps);
    status_msg_.map_centre_down.reserve(maps);
    status_msg_.map_updates.reserve(maps);
    objects_msg_.objects.reserve(m.segmentation.max_objects);
    const std::size_t voxels = mapper_.map().size();
    snapshot_msg_.index.reserve(voxels);
    snapshot_msg_.log_odds.reserve(voxels);
    snapshot_msg_.flags.reserve(voxels);
}

// Counters and time stamps come off the network: differences are taken in
// unsigned arithmetic (well defined for any pair once ordered) and sums saturate.
// Only forward steps count gaps: a repeated or older seq (a duplicate, a
// hostile copy) neither counts nor moves the reference back, so one bad message
// cannot fake gaps later. A seq far behind (a restarted publisher) re-bases.
void MapperNode::trackSeq(int channel, int64_t seq) {
    const int64_t last = last_seq_[channel];
    if (last >= 0 && seq > last) {
        const uint64_t missed = static_cast<uint64_t>(seq) - static_cast<uint64_t>(last) - 1u;
        const uint64_t room = static_cast<uint64_t>(INT64_MAX - gaps_[channel]);
        gaps_[channel] += static_cast<int64_t>(std::min(missed, room));
    }
    constexpr uint64_t kRestart = 1000000;
    if (last < 0 || seq > last ||
        (seq >= 0 && static_cast<uint64_t>(last) - static_cast<uint64_t>(seq) > kRestart))
        last_seq_[channel] = seq;
}

void MapperNode::countRefusal(guard::Verdict v) {
    switch (v) {
        case guard::Verdict::BadFingerprint: ++rejects_[static_cast<int>(TransportReject::BadFingerprint)]; return;
        case guard::Verdict::Truncated: ++rejects_[static_cast<int>(TransportReject::Truncated)]; return;
        case guard::Verdict::Trailing: ++rejects_[static_cast<int>(TransportReject::TrailingBytes)]; return;
        case guard::Verdict::BadCount: ++rejects_[static_cast<int>(TransportReject::BadCount)]; return;
        case guard::Verdict::Ok: ++rejects_[static_cast<int>(TransportReject::Malformed)]; return;
    }
}

int64_t MapperNode::refusedBytes() const {
    int64_t n = 0;
    for (TransportReject r : {TransportReject::Malformed, TransportReject::BadFingerprint, TransportReject::Truncated,
                              TransportReject::TrailingBytes, TransportReject::BadCount})
        n += rejects_[static_cast<int>(r)];
    return n;
}

void MapperNode::handle(const std::string& channel, const void* data, std::size_t size) {
    if (channel == cfg_.nav_channel) onNav(data, size);
    else if (channel == cfg_.fls_channel) onFls(data, size);
    else if (channel == cfg_.ps_channel) onPs(data, size);
}

void MapperNode::onNav(const void* data, std::size_t size) {
    const guard::Verdict v = guard::checkNav(data, size);
    if (v != guard::Verdict::Ok || nav_msg_.decode(data, 0, static_cast<int>(size)) < 0) {
        countRefusal(v);
        return;
    }
    trackSeq(kNav, nav_msg_.seq);
    const TimedPose p = timedPoseOf(nav_msg_);
    // A confirmed NAV time jump replaces the NAV history: first settle what
    // arrived before the new timeline began, against the old one.
    if (mapper_.navWouldReset(p)) flushOrdered(true, nav_epoch_);
    const bool was_pending = mapper_.navTimelinePending();
    const Outcome o = mapper_.addNav(p);
    if (o == Outcome::NavTimeJump && (!was_pending || mapper_.navCandidateCount() == 1)) ++nav_epoch_;
    newest_nav_utime_ = mapper_.newestNavUtime().value_or(INT64_MIN);
    flush(false);
    // A map the vehicle has left is frozen by this NAV (Mapper::addNav), so
    // finalising it here gives the same map live and offline.
    finaliseLeftMaps();
    // Periodic outputs run on accepted NAV time only: a glitch stamp must not
    // drive them (issue 10, finding 3).
    if (o == Outcome::Used) maybePeriodic(newest_nav_utime_);
}

void MapperNode::finaliseLeftMaps() {
    for (int s = mapper_.leavingSlot(); s >= 0; s = mapper_.leavingSlot()) {
        const int id = mapper_.slot(s).id;
        if (id == 1) first_origin_ = mapper_.slotMap(s).origin(), first_centre_ = mapper_.slotMap(s).centre();
        const std::vector<ObjectInfo>& objects = mapper_.finaliseSlot(s);
        publishObjects(id, objects);
        if (out_.finalised) out_.finalised(FinalisedMap{id, mapper_.slotMap(s), mapper_.segmenter(), objects});
        mapper_.releaseSlot(s);
    }
}

void MapperNode::finish() {
    mapper_.leaveAll();
    finaliseLeftMaps();
}

template <class Msg>
void MapperNode::enqueue(std::vector<Pending<Msg>>& slots, guard::Verdict verdict, int channel, const void* data,
                         std::size_t size) {
    if (verdict != guard::Verdict::Ok) {
        countRefusal(verdict);
        return;
    }
    auto is_free = [](const Pending<Msg>& p) { return !p.used; };
    auto slot = std::find_if(slots.begin(), slots.end(), is_free);  // there is always one (see the constructor)
    if (slot->msg.decode(data, 0, static_cast<int>(size)) < 0) {
        countRefusal(guard::Verdict::Ok);
        return;
    }
    const int64_t utime = slot->msg.utime, seq = slot->msg.seq;
    // Processing runs in (utime, seq) order per channel: a copy of a message
    // already processed or waiting would be counted twice, and an older one
    // would be processed out of order; both are refused (the map stays that of
    // the valid messages alone).
    bool duplicate = utime == done_utime_[channel] && seq == done_seq_[channel];
    for (const auto& p : slots) duplicate |= p.used && p.msg.utime == utime && p.msg.seq == seq;
    if (duplicate) {
        ++rejects_[static_cast<int>(TransportReject::Duplicate)];
        return;
    }
    if (utime < done_utime_[channel] || (utime == done_utime_[channel] && seq < done_seq_[channel])) {
        ++rejects_[static_cast<int>(TransportReject::Stale)];
        return;
    }
    trackSeq(channel, seq);
    slot->used = true;
    slot->arrival_wall_us = wallUs();
    slot->nav_epoch = nav_epoch_;
    if (std::find_if(slots.begin(), slots.end(), is_free) == slots.end()) {
        thinOne(slots);
        ++rejects_[static_cast<int>(TransportReject::PendingOverflow)];
    }
    flush(false);
}

void MapperNode::onFls(const void* data, std::size_t size) {
    enqueue(fls_pending_, guard::checkFls(data, size, limits_), kFls, data, size);
}

void MapperNode::onPs(const void* data, std::size_t size) {
    enqueue(ps_pending_, guard::checkPs(data, size, limits_), kPs, data, size);
}

// Sonar messages are processed only once a NAV strictly after them has arrived
// (or on force), in (utime, PS before FLS, seq) order: the map then never
// depends on how the transport interleaved the channels. While NAV samples are
// held as a possible new timeline, nothing is processed (unless forced).
void MapperNode::flush(bool force) {
    if (!force && mapper_.navTimelinePending()) return;
    flushOrdered(force, INT64_MAX);
}

void MapperNode::flushOrdered(bool force, int64_t before_epoch) {
    for (;;) {
        PendingPs* ps = oldestPending(ps_pending_, before_epoch);
        PendingFls* fls = oldestPending(fls_pending_, before_epoch);
        if (!ps && !fls) return;
        const bool take_ps = ps && (!fls || sonarBefore({ps->msg.utime, SonarKind::Ps, ps->msg.seq},
                                                          {fls->msg.utime, SonarKind::Fls, fls->msg.seq}));
        const int64_t utime = take_ps ? ps->msg.utime : fls->msg.utime;
        if (!force && !sonarReleased(utime, newest_nav_utime_)) return;
        if (take_ps) {
            done_utime_[kPs] = ps->msg.utime, done_seq_[kPs] = ps->msg.seq;
            processPs(ps->msg);
            ps->used = false;
        } else {
            done_utime_[kFls] = fls->msg.utime, done_seq_[kFls] = fls->msg.seq;
            processFls(fls->msg);
            fls->used = false;
        }
    }
}

int MapperNode::pendingCount() const {
    int n = 0;
    for (const auto& p : fls_pending_) n += p.used;
    for (const auto& p : ps_pending_) n += p.used;
    return n;
}

void MapperNode::tick(int64_t now_wall_us) {
    bool stale = false;
    for (const auto& p : ps_pending_) stale |= p.used && now_wall_us - p.arrival_wall_us > cfg_.nav_wait_timeout_us;
    for (const auto& p : fls_pending_) stale |= p.used && now_wall_us - p.arrival_wall_us > cfg_.nav_wait_timeout_us;
    if (stale) flush(true);
}

bool MapperNode::flsGeometryMatches(const fls_image_t& m) const {
    const MapperConfig& c = cfg_.mapper;
    // The mounting (position, roll, yaw) and the tilt are the vehicle's, from the
    // config, and must agree with the message (issue 10, finding 5): NaN or 0
    // there is a misconfigured driver. Ranges, bearings and the aperture are the
    // ping's own (per-ping geometry): libfusion takes them from the frame and
    // checks them (fls_bad_geometry).
    constexpr double kAngleTol = 0.5 * kDegToRad, kMountTol = 0.01;
    return near(m.tilt, c.fls.tilt, kAngleTol) && near(m.mount_xyz[0], c.fls_mount.x, kMountTol) &&
           near(m.mount_xyz[1], c.fls_mount.y, kMountTol) && near(m.mount_xyz[2], c.fls_mount.z, kMountTol) &&
           near(m.mount_roll_yaw[0], c.fls_mount.roll, kAngleTol) && near(m.mount_roll_yaw[1], c.fls_mount.yaw, kAngleTol);
}

bool MapperNode::psGeometryMatches(const ps_ping_t& m) const {
    const MapperConfig& c = cfg_.mapper;
    constexpr double kAngleTol = 0.5 * kDegToRad, kMountTol = 0.01, kHeadTol = 1.0 * kDegToRad;
    if (!near(m.tilt, c.ps.tilt, kAngleTol) || !near(m.fan_min, c.ps.fan_min, kAngleTol) ||
        !near(m.fan_max, c.ps.fan_max, kAngleTol) || !near(m.mount_xyz[0], c.ps_mount.x, kMountTol) ||
        !near(m.mount_xyz[1], c.ps_mount.y, kMountTol) || !near(m.mount_xyz[2], c.ps_mount.z, kMountTol) ||
        !near(m.mount_roll_yaw[0], c.ps_mount.roll, kAngleTol) || !near(m.mount_roll_yaw[1], c.ps_mount.yaw, kAngleTol))
        return false;
    // The head sweeps its configured sector; the range window may be shorter than
    // the sonar's (a range setting) but not longer: a 100 m ping from a 10 m sonar
    // would anchor the map 0.8 m off (finding 5).
    if (!(m.head_angle >= c.ps.head_min - kHeadTol && m.head_angle <= c.ps.head_max + kHeadTol)) return false;
    const double bin = (c.ps.range_max - c.ps.range_min) / std::max(1, c.ps.bins - 1);
    if (!(m.range_min >= c.ps.range_min - bin && m.range_max <= c.ps.range_max + bin)) return false;
    return true;
}

void MapperNode::processFls(fls_image_t& m) {
    const auto start = std::chrono::steady_clock::now();
    if (!flsGeometryMatches(m)) {
        ++rejects_[static_cast<int>(TransportReject::FlsGeometryMismatch)];
        return;
    }
    FlsFrame f;
    f.utime = m.utime;
    f.rows = m.num_ranges;
    f.cols = m.num_beams;
    f.data = reinterpret_cast<const uint8_t*>(m.data.data());
    f.data_size = m.data.size();
    if (static_cast<int64_t>(m.data_size) != static_cast<int64_t>(m.num_ranges) * m.num_beams) f.data_size = 0;
    // The ping's own geometry (lcm-gen sized both arrays from the counts).
    f.row_range = m.row_range.size() == static_cast<std::size_t>(std::max(0, m.num_ranges)) ? m.row_range.data() : nullptr;
    f.beam_bearing =
        m.beam_bearing.size() == static_cast<std::size_t>(std::max(0, m.num_beams)) ? m.beam_bearing.data() : nullptr;
    f.elevation_min = m.elevation_min;
    f.elevation_max = m.elevation_max;
    // Output stamps follow data that was used: a rejected INT64_MAX stamp must
    // not stamp every later status (finding 3).
    if (mapper_.addFls(f) == Outcome::Used) newest_data_utime_ = std::max(newest_data_utime_, m.utime);
    recordTime(start);
}

void MapperNode::processPs(ps_ping_t& m) {
    const auto start = std::chrono::steady_clock::now();
    if (!psGeometryMatches(m)) {
        ++rejects_[static_cast<int>(TransportReject::PsGeometryMismatch)];
        return;
    }
    PsPing p;
    p.utime = m.utime;
    p.head_angle = m.head_angle;
    p.range_min = m.range_min;
    p.range_max = m.range_max;
    p.bins = m.num_bins;
    p.intensity = reinterpret_cast<const uint8_t*>(m.intensity.data());
    if (mapper_.addPs(p) == Outcome::Used) newest_data_utime_ = std::max(newest_data_utime_, m.utime);
    recordTime(start);
}

void MapperNode::recordTime(std::chrono::steady_clock::time_point start) {
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    proc_last_us_ = us;
    proc_max_us_ = std::max(proc_max_us_, us);
    proc_us_[proc_count_ % proc_us_.size()] = us;
    ++proc_count_;
    if (us > cfg_.budget_us) ++overruns_;
}

double MapperNode::p99Us() const {
    const std::size_t n = std::min(proc_count_, proc_us_.size());
    if (n == 0) return 0.0;
    std::copy(proc_us_.begin(), proc_us_.begin() + static_cast<std::ptrdiff_t>(n), scratch_.begin());
    const std::size_t k = std::min(n - 1, static_cast<std::size_t>(std::ceil(0.99 * n)) - 1);
    std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k),
                     scratch_.begin() + static_cast<std::ptrdiff_t>(n));
    return scratch_[k];
}

void MapperNode::maybePeriodic(int64_t utime) {
    auto due = [&](int64_t& last, double period_s) {
        if (period_s <= 0.0) return false;
        // Due on the first call, when data time went backwards (a new log), or
        // when a period has passed.
        if (last == INT64_MIN || utime < last ||
            static_cast<uint64_t>(utime) - static_cast<uint64_t>(last) >= static_cast<uint64_t>(period_s * 1e6)) {
            last = utime;
            return true;
        }
        return false;
    };
    if (due(last_status_utime_, cfg_.status_period_s)) publishStatus();
    if (out_.checkpoint && due(last_checkpoint_utime_, cfg_.checkpoint_period_s)) out_.checkpoint();
    if (mapper_.activeMaps() > 0 && due(last_segment_utime_, cfg_.segment_period_s)) segmentAndPublish();
    if (out_.map && mapper_.map().initialised() && due(last_map_utime_, cfg_.map_period_s)) {
        map_snapshot_t& snap = snapshot_msg_;
        snap.index.clear();
        snap.log_odds.clear();
        snap.flags.clear();
        snap.utime = utime;
        snap.seq = map_seq_++;
        const VoxelMap& vm = mapper_.map();
        for (int i = 0; i < 3; ++i) snap.origin[i] = vm.origin()[i];
        snap.resolution = vm.resolution();
        snap.dims[0] = vm.nx(), snap.dims[1] = vm.ny(), snap.dims[2] = vm.nz();
        const float thr = static_cast<float>(logOddsFromProbability(cfg_.mapper.segmentation.occupied_probability));
        for (std::size_t i = 0; i < vm.size(); ++i) {
            if (vm.logOdds(i) <= thr) continue;
            snap.index.push_back(static_cast<int32_t>(i));
            snap.log_odds.push_back(vm.logOdds(i));
            snap.flags.push_back(static_cast<int8_t>(vm.flags(i)));
        }
        snap.num_voxels = static_cast<int32_t>(snap.index.size());
        out_.map(snap);
    }
}

void MapperNode::segmentAndPublish() {
    for (int s = 0; s < mapper_.slotCount(); ++s) {
        if (!mapper_.slot(s).inUse()) continue;  // free, or finalised and parked
        mapper_.segmentSlot(s);
        publishObjects(mapper_.slot(s).id, mapper_.segmenter().objects());
    }
}

void MapperNode::publishObjects(int map_id, const std::vector<ObjectInfo>& objects) {
    if (!out_.objects) return;
    objects_t& msg = objects_msg_;
    msg.objects.clear();
    msg.utime = newest_data_utime_;
    msg.seq = objects_seq_++;
    for (const ObjectInfo& o : objects) {
        object_t t;
        t.id = o.id;
        t.map_id = map_id;
        t.ps_confirmed = o.ps_confirmed;
        t.voxel_count = o.voxel_count;
        t.volume_m3 = o.volume_m3;
        t.height_m = o.height_m;
        for (int i = 0; i < 3; ++i) {
            t.centroid[i] = o.centroid[i];
            t.bbox_min[i] = o.bbox_min[i];
            t.bbox_max[i] = o.bbox_max[i];
        }
        msg.objects.push_back(t);
    }
    msg.num_objects = static_cast<int32_t>(msg.objects.size());
    out_.objects(msg);
}

const mapper_status_t& MapperNode::status() {
    mapper_status_t& s = status_msg_;
    s.utime = newest_data_utime_;
    s.seq = status_seq_;
    s.state = mapper_.counters().map_initialisations > 0 ? "mapping" : "idle";
    // The first map (id 1): while it is being made, its slot; once finalised,
    // where it was (its slot may be free or hold another map by then).
    for (int k = 0; k < mapper_.slotCount(); ++k)
        if (mapper_.slot(k).id == 1) first_origin_ = mapper_.slotMap(k).origin(), first_centre_ = mapper_.slotMap(k).centre();
    s.map_ids.clear();
    s.map_centre_north.clear();
    s.map_centre_east.clear();
    s.map_centre_down.clear();
    s.map_updates.clear();
    for (int k = 0; k < mapper_.slotCount(); ++k) {  // capacity reserved at start-up
        if (!mapper_.slot(k).inUse()) continue;  // free, or finalised and parked
        const Eigen::Vector3d c = mapper_.slotMap(k).centre();
        s.map_ids.push_back(mapper_.slot(k).id);
        s.map_centre_north.push_back(c.x());
        s.map_centre_east.push_back(c.y());
        s.map_centre_down.push_back(c.z());
        s.map_updates.push_back(mapper_.slot(k).updates);
    }
    s.num_maps = static_cast<int32_t>(s.map_ids.size());
    for (int i = 0; i < 3; ++i) {
        s.map_origin[i] = first_origin_[i];
        s.map_centre[i] = first_centre_[i];
    }
    const MapperCounters& c = mapper_.counters();
    s.nav_in = c.nav_in;
    s.fls_in = c.fls_in;
    s.ps_in = c.ps_in;
    s.fls_used = c.fls_used;
    s.ps_used = c.ps_used;
    s.maps_finalised = c.maps_finalised;
    s.detections = c.detections;
    s.detection_no_free_map = c.detection_no_free_map;
    // Names were filled at start-up in this same order.
    std::size_t r = 0;
    for (int i = 1; i < kOutcomeCount; ++i) s.reason_count[r++] = c.by_outcome[i];
    for (int i = 0; i < static_cast<int>(TransportReject::kCount); ++i) s.reason_count[r++] = rejects_[i];
    s.nav_seq_gaps = gaps_[kNav];
    s.fls_seq_gaps = gaps_[kFls];
    s.ps_seq_gaps = gaps_[kPs];
    s.proc_last_us = proc_last_us_;
    s.proc_max_us = proc_max_us_;
    s.proc_p99_us = p99Us();
    s.budget_overruns = overruns_;
    s.budget_us = cfg_.budget_us;
    return s;
}

void MapperNode::publishStatus() {
    if (!out_.status) return;
    out_.status(status());
    ++status_seq_;
}

namespace {
template <class Msg>
std::size_t encodedBound(const MapperConfig& m);
template <>
std::size_t encodedBound<fls_image_t>(const MapperConfig& m) {
    return 256 + 256 + 4 * static_cast<std::size_t>(m.fls.beams + m.fls.rows) +
           static_cast<std::size_t>(m.fls.beams) * m.fls.rows;
}
template <>
std::size_t encodedBound<ps_ping_t>(const MapperConfig& m) {
    return 256 + 256 + static_cast<std::size_t>(m.ps.bins);
}

// Waiting messages in (utime, seq) order, whatever slots they sit in, so equal
// states give equal bytes (no allocation: a selection over the few slots).
template <class P>
void savePending(StateWriter& w, const std::vector<P>& slots) {
    uint64_t n = 0;
    for (const P& p : slots) n += p.used;
    w.pod(n);
    const P* prev = nullptr;
    for (uint64_t i = 0; i < n; ++i) {
        const P* next = nullptr;
        for (const P& q : slots)
            if (q.used && (!prev || earlier(*prev, q)) && (!next || earlier(q, *next))) next = &q;
        if (!next) break;
        prev = next;
        const P& p = *next;
        const int size = p.msg.getEncodedSize();
        w.pod(p.nav_epoch);
        w.pod(static_cast<uint32_t>(size));
        if (uint8_t* at = w.reserve(static_cast<std::size_t>(size))) p.msg.encode(at, 0, size);
    }
}

template <class P, class Check>
bool loadPending(StateReader& r, std::vector<P>& slots, Check check) {
    uint64_t n = 0;
    if (!r.pod(n) || n >= slots.size()) return false;
    for (P& p : slots) p.used = false;
    for (uint64_t i = 0; i < n; ++i) {
        int64_t epoch = 0;
        uint32_t size = 0;
        if (!r.pod(epoch) || !r.pod(size)) return false;
        const uint8_t* bytes = r.view(size);
        if (!bytes || !check(bytes, size) || slots[i].msg.decode(bytes, 0, static_cast<int>(size)) < 0) return false;
        slots[i].used = true;
        slots[i].nav_epoch = epoch;
        slots[i].arrival_wall_us = wallUs();
    }
    return true;
}
}  // namespace

std::size_t MapperNode::stateBytesBound() const {
    const MapperConfig& m = cfg_.mapper;
    return mapper_.stateBytesBound() + 1024 + fls_pending_.size() * (16 + encodedBound<fls_image_t>(m)) +
           ps_pending_.size() * (16 + encodedBound<ps_ping_t>(m));
}

void MapperNode::saveState(StateWriter& w) const {
    mapper_.saveState(w);
    w.pod(last_seq_);
    w.pod(gaps_);
    w.pod(done_utime_);
    w.pod(done_seq_);
    w.pod(rejects_);
    for (int64_t v : {nav_epoch_, status_seq_, objects_seq_, map_seq_, last_status_utime_, last_segment_utime_,
                      last_map_utime_, last_checkpoint_utime_, newest_data_utime_, input_position_, overruns_})
        w.pod(v);
    savePending(w, fls_pending_);
    savePending(w, ps_pending_);
}

bool MapperNode::loadState(StateReader& r) {
    if (!mapper_.loadState(r) || !r.pod(last_seq_) || !r.pod(gaps_) || !r.pod(done_utime_) || !r.pod(done_seq_) ||
        !r.pod(rejects_))
        return false;
    for (int64_t* v : {&nav_epoch_, &status_seq_, &objects_seq_, &map_seq_, &last_status_utime_, &last_segment_utime_,
                       &last_map_utime_, &last_checkpoint_utime_, &newest_data_utime_, &input_position_, &overruns_})
        if (!r.pod(*v)) return false;
    const bool ok =
        loadPending(r, fls_pending_,
                    [&](const uint8_t* b, std::size_t n) { return guard::checkFls(b, n, limits_) == guard::Verdict::Ok; }) &&
        loadPending(r, ps_pending_,
                    [&](const uint8_t* b, std::size_t n) { return guard::checkPs(b, n, limits_) == guard::Verdict::Ok; });
    if (!ok || !r.atEnd()) return false;
    newest_nav_utime_ = mapper_.newestNavUtime().value_or(INT64_MIN);
    return true;
}

}  // namespace sonarfusion
