#include "update_stream.hpp"

#include "message_convert.hpp"
#include "sonar_order.hpp"

#include <lcm/lcm-cpp.hpp>
#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "sonarfusion/update_sink.hpp"
#include "sonarfusion/voxel_walk.hpp"

namespace sfbench {

using namespace sonarfusion;

ScenarioLog loadScenarioLog(const std::string& path, const DaemonConfig& cfg) {
    lcm::LogFile file(path, "r");
    if (!file.good()) throw std::runtime_error("cannot read LCM log " + path);
    ScenarioLog log;
    nav_state_t nav;
    fls_image_t fls;
    ps_ping_t ps;
    while (const lcm::LogEvent* ev = file.readNextEvent()) {
        const int len = static_cast<int>(ev->datalen);
        if (ev->channel == cfg.nav_channel) {
            if (nav.decode(ev->data, 0, len) < 0) throw std::runtime_error(path + ": bad NAV message");
            log.nav.push_back(timedPoseOf(nav));
        } else if (ev->channel == cfg.fls_channel) {
            if (fls.decode(ev->data, 0, len) < 0) throw std::runtime_error(path + ": bad FLS message");
            FlsMessage m;
            m.utime = fls.utime;
            m.seq = fls.seq;
            m.rows = fls.num_ranges;
            m.cols = fls.num_beams;
            m.data.assign(fls.data.begin(), fls.data.end());
            m.size_ok = static_cast<int64_t>(fls.data_size) == static_cast<int64_t>(fls.num_ranges) * fls.num_beams;
            log.fls.push_back(std::move(m));
        } else if (ev->channel == cfg.ps_channel) {
            if (ps.decode(ev->data, 0, len) < 0) throw std::runtime_error(path + ": bad PS message");
            PsMessage m;
            m.utime = ps.utime;
            m.seq = ps.seq;
            m.head_angle = ps.head_angle;
            m.range_min = ps.range_min;
            m.range_max = ps.range_max;
            m.intensity.assign(ps.intensity.begin(), ps.intensity.end());
            log.ps.push_back(std::move(m));
        }
    }

    // Sonar in the daemon's order (sonar_order.hpp, the daemon's own rule).
    struct Key {
        SonarKey key;
        uint32_t index;
    };
    std::vector<Key> sonar;
    for (uint32_t i = 0; i < log.ps.size(); ++i) sonar.push_back({{log.ps[i].utime, SonarKind::Ps, log.ps[i].seq}, i});
    for (uint32_t i = 0; i < log.fls.size(); ++i) sonar.push_back({{log.fls[i].utime, SonarKind::Fls, log.fls[i].seq}, i});
    std::stable_sort(sonar.begin(), sonar.end(), [](const Key& a, const Key& b) { return sonarBefore(a.key, b.key); });
    auto emitSonar = [&](const Key& k) {
        log.order.push_back({k.key.kind == SonarKind::Ps ? ScenarioLog::Event::Ps : ScenarioLog::Event::Fls, k.index});
    };
    std::size_t next = 0;
    int64_t newest_nav = INT64_MIN;
    for (uint32_t i = 0; i < log.nav.size(); ++i) {
        log.order.push_back({ScenarioLog::Event::Nav, i});
        if (log.nav[i].pose.isFinite() && log.nav[i].utime > newest_nav) newest_nav = log.nav[i].utime;
        while (next < sonar.size() && sonarReleased(sonar[next].key.utime, newest_nav)) emitSonar(sonar[next++]);
    }
    while (next < sonar.size()) emitSonar(sonar[next++]);  // the daemon's final flush(true)
    return log;
}

FlsFrame frameOf(const FlsMessage& m) {
    FlsFrame f;
    f.utime = m.utime;
    f.rows = m.rows;
    f.cols = m.cols;
    f.data = m.data.data();
    f.data_size = m.size_ok ? m.data.size() : 0;  // as the daemon: a size that disagrees is refused
    return f;
}

Outcome feedEvent(const ScenarioLog& log, const ScenarioLog::Event& ev, Mapper& mapper) {
    switch (ev.kind) {
        case ScenarioLog::Event::Nav: return mapper.addNav(log.nav[ev.index]);
        case ScenarioLog::Event::Fls: {
            return mapper.addFls(frameOf(log.fls[ev.index]));
        }
        case ScenarioLog::Event::Ps: {
            const PsMessage& m = log.ps[ev.index];
            PsPing p;
            p.utime = m.utime;
            p.head_angle = m.head_angle;
            p.range_min = m.range_min;
            p.range_max = m.range_max;
            p.bins = static_cast<int>(m.intensity.size());
            p.intensity = m.intensity.data();
            return mapper.addPs(p);
        }
    }
    return Outcome::NoPose;
}

namespace {

// Records the updates libfusion's own updaters hand to their sink (the very
// code the Mapper runs), in their order, into the stream.
// The PS carver decides from the echo and crossing counts a voxel holds before
// each ray (UpdateConfig::ps_carve_spare_echo_share), so the sink keeps those
// counts in `counts`, a map that sees exactly the PS rays the Mapper's does.
class StreamSink {
public:
    StreamSink(UpdateStream& out, bool fls, VoxelMap& counts)
        : out_(out), fls_(fls), counts_(counts), crossings_(counts.writer()) {}
    void add(std::size_t v, float delta, uint8_t flag) {
        out_.updates.push_back({static_cast<uint32_t>(v), delta});
        out_.update_flag.push_back(flag);
        if (out_.flag_runs.empty() || out_.flag_runs.back().flag != flag)
            out_.flag_runs.push_back({static_cast<uint32_t>(out_.updates.size() - 1), flag});
        ++(fls_ ? out_.fls_updates : out_.ps_updates);
        if (!fls_ && !out_.rays.empty()) out_.rays.back().end_update = static_cast<uint32_t>(out_.updates.size());
    }
    // Flags and echo and crossing counts are not part of the log-odds stream.
    void echo(std::size_t v) { counts_.addPsEcho(v); }
    void crossed(std::size_t v) { crossings_.addPsCrossing(v); }
    void aboveSeabed(std::size_t /*v*/) {}  // nor the above-seabed vote counts
    void ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& carve_end, const Eigen::Vector3d& echo) {
        const auto at = static_cast<uint32_t>(out_.updates.size());
        out_.rays.push_back(CarvingRay{origin, carve_end, echo, at, at});
    }

private:
    UpdateStream& out_;
    bool fls_;
    VoxelMap& counts_;
    VoxelMap::Writer crossings_;
};

}  // namespace

template <uint8_t Flag>
void replayRun(const VoxelUpdate* u, std::size_t begin, std::size_t end, MapWriterSink& sink) {
    for (std::size_t i = begin; i < end; ++i) sink.add(u[i].voxel, u[i].delta, Flag);
}

void replayStream(const UpdateStream& stream, std::size_t count, VoxelMap& map) {
    // Through the Mapper's own sink (MapWriterSink: VoxelMap::Writer, whose
    // locals keep the map's data pointers and clamp bounds out of the flag
    // store's aliasing), run by run with the flag a constant, as the updaters
    // call it: a flag of 0 (the FLS's free space) stores nothing, the others
    // one plain byte store into their plane.
    const VoxelUpdate* u = stream.updates.data();
    MapWriterSink sink(map);
    const auto& runs = stream.flag_runs;
    for (std::size_t r = 0; r < runs.size() && runs[r].begin < count; ++r) {
        const std::size_t begin = runs[r].begin;
        const std::size_t end = r + 1 < runs.size() ? std::min<std::size_t>(runs[r + 1].begin, count) : count;
        switch (runs[r].flag) {
            case 0: replayRun<0>(u, begin, end, sink); break;
            case VoxelMap::kPsObserved: replayRun<VoxelMap::kPsObserved>(u, begin, end, sink); break;
            case VoxelMap::kFlsTouched: replayRun<VoxelMap::kFlsTouched>(u, begin, end, sink); break;
            default:  // no updater sets another flag; kept exact all the same
                for (std::size_t i = begin; i < end; ++i) sink.add(u[i].voxel, u[i].delta, runs[r].flag);
        }
    }
}

Recording recordUpdateStream(const ScenarioLog& log, const MapperConfig& cfg) {
    Recording rec;
    UpdateStream& s = rec.stream;
    Mapper mapper(cfg);
    NavBuffer nav(cfg.nav_buffer_capacity, cfg.max_nav_gap_us);
    FlsUpdater fls_recorder(mapper.flsModel(), cfg.update, mapper.map());  // its own scratch
    PsCarver ps_recorder(mapper.psModel(), cfg.update);
    VoxelMap counts(cfg.map);  // the PS echo and crossing counts the carver decides from
    // DetectorConfig::replay_fls_frames: the frames the Mapper holds (the last
    // that many of the configured geometry it judged, map or not), recorded as
    // FLS messages when it anchors the map, in their order, as it applies them.
    struct Held {
        uint32_t source;
        Eigen::Isometry3d world_from_sensor;
        std::optional<SeabedFit> seabed;
    };
    std::vector<Held> held;
    const std::size_t hold_capacity = static_cast<std::size_t>(cfg.detector.replay_fls_frames);
    const auto recordFls = [&](uint32_t source, const Eigen::Isometry3d& world_from_sensor,
                               const std::optional<SeabedFit>& seabed) {
        MessageRecord m{};
        m.source = source;
        m.begin = static_cast<uint32_t>(s.updates.size());
        m.kind = MessageRecord::Fls;
        m.world_from_sensor = world_from_sensor;
        m.seabed = seabed;
        fls_recorder.setSeabed(m.seabed);
        StreamSink sink(s, true, counts);
        fls_recorder.apply(frameOf(log.fls[source]), m.world_from_sensor, mapper.map(), sink);
        ++s.fls_frames;
        m.end = static_cast<uint32_t>(s.updates.size());
        s.messages.push_back(m);
    };

    // DetectorConfig::replay_pings: the PS pings the Mapper holds (every one
    // with a selected echo, map or not), carved into the map when it is
    // anchored, before the held frames, where they reach it.
    std::vector<MessageRecord> held_pings;
    const std::size_t ping_capacity = cfg.update.ps_carving_enabled ? static_cast<std::size_t>(cfg.detector.replay_pings) : 0;
    const auto psMessage = [&](uint32_t index, const Eigen::Isometry3d& world_from_sensor, MessageRecord& m) {
        const PsMessage& p = log.ps[index];
        PsPing ping;
        ping.head_angle = p.head_angle;
        ping.range_min = p.range_min;
        ping.range_max = p.range_max;
        ping.bins = static_cast<int>(p.intensity.size());
        ping.intensity = p.intensity.data();
        const std::optional<PsEchoGroup> group = closestGroup(ping, cfg.ps_selection);
        if (!group) return false;
        m = MessageRecord{};
        m.source = index;
        m.kind = MessageRecord::Ps;
        m.world_from_sensor = world_from_sensor;
        m.head_angle = p.head_angle;
        m.range = rangeOfBin(ping, group->peak);
        m.echo_strength = ping.intensity[group->peak] / 255.0;
        m.carve_range = carveStopRange(ping, *group, cfg.ps_selection, cfg.update.ps_carve_noise_sigmas,
                                       cfg.update.ps_carve_echo_window_voxels * cfg.map.resolution);
        return true;
    };
    const auto recordPs = [&](MessageRecord m) {
        m.begin = static_cast<uint32_t>(s.updates.size());
        m.ray_begin = static_cast<uint32_t>(s.rays.size());
        StreamSink sink(s, false, counts);
        if (m.carve_only) {
            CarvingOnlySink<StreamSink> water(sink);
            ps_recorder.apply(m.head_angle, m.range, m.world_from_sensor, counts, water, m.echo_strength, m.carve_range);
        } else {
            ps_recorder.apply(m.head_angle, m.range, m.world_from_sensor, counts, sink, m.echo_strength, m.carve_range);
        }
        m.ray_end = static_cast<uint32_t>(s.rays.size());
        ++s.ps_pings;
        m.end = static_cast<uint32_t>(s.updates.size());
        s.messages.push_back(m);
    };
    for (const ScenarioLog::Event& ev : log.order) {
        if (ev.kind == ScenarioLog::Event::Nav) {
            nav.add(log.nav[ev.index]);
            feedEvent(log, ev, mapper);
            continue;
        }
        const bool mapping = mapper.map().initialised();
        const Outcome outcome = feedEvent(log, ev, mapper);
        Pose pose;
        if (hold_capacity > 0 && ev.kind == ScenarioLog::Event::Fls &&
            (outcome == Outcome::Used || outcome == Outcome::FlsBeforeMap) &&
            log.fls[ev.index].data.size() == static_cast<std::size_t>(cfg.fls.rows) * cfg.fls.beams &&
            nav.poseAt(log.fls[ev.index].utime, pose) == PoseLookup::Ok) {
            if (held.size() == hold_capacity) held.erase(held.begin());
            held.push_back({static_cast<uint32_t>(ev.index), sensorToWorld(pose, cfg.fls_mount), mapper.lastFlsSeabed()});
        }
        MessageRecord ping_record;
        if (ping_capacity > 0 && ev.kind == ScenarioLog::Event::Ps &&
            (outcome == Outcome::Used || outcome == Outcome::PsNoEcho) &&
            nav.poseAt(log.ps[ev.index].utime, pose) == PoseLookup::Ok &&
            psMessage(static_cast<uint32_t>(ev.index), sensorToWorld(pose, cfg.ps_mount), ping_record)) {
            if (held_pings.size() == ping_capacity) held_pings.erase(held_pings.begin());
            ping_record.carve_only = cfg.detector.replay_pings_carve_only;
            held_pings.push_back(ping_record);
        }
        if (!mapping && mapper.map().initialised()) {
            counts.initialiseAt(mapper.map().centre());
            if (counts.origin() != mapper.map().origin()) throw std::runtime_error("recorder: count map origin differs from the Mapper's");
            for (const MessageRecord& h : held_pings)
                if (mapper.map().distanceTo(h.world_from_sensor.translation()) <= log.ps[h.source].range_max)
                    recordPs(h);  // as Mapper::reaches
            for (const Held& h : held) recordFls(h.source, h.world_from_sensor, h.seabed);
        }
        if (!mapping || outcome != Outcome::Used) continue;
        if (ev.kind == ScenarioLog::Event::Fls) {
            const FlsMessage& f = log.fls[ev.index];
            if (nav.poseAt(f.utime, pose) != PoseLookup::Ok) throw std::runtime_error("recorder: no pose for a used FLS frame");
            recordFls(static_cast<uint32_t>(ev.index), sensorToWorld(pose, cfg.fls_mount), mapper.lastFlsSeabed());
            continue;
        }
        if (!cfg.update.ps_carving_enabled) continue;
        if (nav.poseAt(log.ps[ev.index].utime, pose) != PoseLookup::Ok) throw std::runtime_error("recorder: no pose for a used PS ping");
        MessageRecord m;
        if (!psMessage(ev.index, sensorToWorld(pose, cfg.ps_mount), m)) continue;  // Used implies a bin was selected
        recordPs(m);
    }
    if (!mapper.map().initialised())
        throw std::runtime_error("the mapper never initialised its map (no object detected): no update stream");
    s.map_origin = mapper.map().origin();
    // The first map's centre (the detector stays armed in survey mode, so its
    // latest detection is not necessarily the one that anchored this map).
    s.map_centre = mapper.map().centre();
    rec.counters = mapper.counters();
    rec.reference_log_odds = mapper.map().logOddsData();

    // The recording is only worth timing if it is the Mapper's stream, exactly.
    VoxelMap replay(cfg.map);
    replay.initialiseAt(s.map_centre);
    if (replay.origin() != s.map_origin) throw std::runtime_error("replay map origin differs from the Mapper's");
    replayStream(s, s.updates.size(), replay);
    if (std::memcmp(replay.logOddsData().data(), rec.reference_log_odds.data(),
                    rec.reference_log_odds.size() * sizeof(float)) != 0)
        throw std::runtime_error("recorded update stream does not reproduce the Mapper's map bit for bit");
    // And its flags: every FLS vote is in the stream; the PS-observed flag the
    // stream sets must be the Mapper's too (the Mapper also sets it at echoes).
    for (std::size_t i = 0; i < replay.size(); ++i)
        if (replay.flsTouched(i) != mapper.map().flsTouched(i) || (replay.psObserved(i) && !mapper.map().psObserved(i)))
            throw std::runtime_error("recorded update stream does not reproduce the Mapper's flags");
    return rec;
}

}  // namespace sfbench
