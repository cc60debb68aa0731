// The exact voxel update stream of a mapper run, recorded once from an LCM log
// so that several map back-ends can be fed the identical updates and timed.
//
// The recording runs the real libfusion Mapper over the log in the daemon's
// order and, beside it, runs libfusion's own FlsUpdater and PsCarver on the
// same messages and poses with a recording sink (update_sink.hpp), so the
// stream comes from the very code the Mapper runs. Replaying the recorded stream into an
// empty VoxelMap must give the Mapper's map bit for bit; replayStream() and
// the bench check that, so the stream is known to be the Mapper's own.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <optional>
#include <vector>

#include "mapper_config_yaml.hpp"
#include "sonarfusion/mapper.hpp"

namespace sfbench {

// One sonar message as read from the log, kept for timing the pipeline.
struct FlsMessage {
    int64_t utime = 0, seq = 0;
    int rows = 0, cols = 0;
    std::vector<uint8_t> data;
    bool size_ok = false;  // data_size == rows * cols, as the daemon checks
};
struct PsMessage {
    int64_t utime = 0, seq = 0;
    double head_angle = 0.0, range_min = 0.0, range_max = 0.0;
    std::vector<uint8_t> intensity;
};

// The whole log in memory, sonar messages in the daemon's processing order.
struct ScenarioLog {
    std::vector<sonarfusion::TimedPose> nav;  // log order
    std::vector<FlsMessage> fls;
    std::vector<PsMessage> ps;
    struct Event {
        enum Kind : uint8_t { Nav, Fls, Ps } kind;
        uint32_t index;  // into nav, fls or ps
    };
    // Mirrors MapperNode: a sonar message is processed once a NAV strictly
    // after it has been used, in (utime, PS before FLS, seq) order; the rest at the end.
    std::vector<Event> order;
};

// Throws std::runtime_error when the log cannot be read.
ScenarioLog loadScenarioLog(const std::string& path, const sonarfusion::DaemonConfig& cfg);

struct VoxelUpdate {
    uint32_t voxel;  // linear index in the VoxelMap
    float delta;     // log-odds increment, applied then clamped
};

// One message that changed the map, with the inputs needed to redo it.
struct MessageRecord {
    enum Kind : uint8_t { Fls, Ps } kind;
    uint32_t source;                         // index into ScenarioLog::fls / ::ps
    Eigen::Isometry3d world_from_sensor;     // pose the Mapper used
    double head_angle = 0.0, range = 0.0;    // PS: phi_p and the selected range r_s
    double carve_range = -1.0;               // PS: where carving stops (negative: at r_s)
    double echo_strength = 1.0;              // PS: the selected bin's intensity / 255
    uint32_t begin = 0, end = 0;             // its updates: stream.updates[begin, end)
    uint32_t ray_begin = 0, ray_end = 0;     // PS: its rays in stream.rays
    std::optional<sonarfusion::SeabedFit> seabed;  // FLS: the seabed plane the Mapper judged its votes against
    bool carve_only = false;  // PS: a held ping carved as water only (DetectorConfig::replay_pings_carve_only)
};

// A PS carving ray (sensor to where carving stops; the echo may lie beyond)
// and its updates, for OctoMap's own ray walk.
struct CarvingRay {
    Eigen::Vector3d origin, end, echo;
    uint32_t begin = 0, end_update = 0;
};

struct UpdateStream {
    Eigen::Vector3d map_origin = Eigen::Vector3d::Zero();  // min corner of the grid
    Eigen::Vector3d map_centre = Eigen::Vector3d::Zero();  // what the Mapper was initialised at
    std::vector<VoxelUpdate> updates;  // in application order
    std::vector<uint8_t> update_flag;  // VoxelMap flag each update sets (same order)
    // The same flags as runs: updates [begin, next run's begin) all set `flag`.
    // The replay loops over runs with the flag a constant, as at each of the
    // updaters' call sites (sink.add(v, delta, VoxelMap::kPsObserved) ...), so
    // it pays no per-update flag read or test the Mapper does not pay.
    struct FlagRun {
        uint32_t begin;
        uint8_t flag;
    };
    std::vector<FlagRun> flag_runs;
    std::vector<MessageRecord> messages;
    std::vector<CarvingRay> rays;
    std::size_t fls_updates = 0, ps_updates = 0;
    int fls_frames = 0, ps_pings = 0;
};

struct Recording {
    UpdateStream stream;
    sonarfusion::MapperCounters counters;
    std::vector<float> reference_log_odds;  // the Mapper's final map
};

// Runs the Mapper over the log and records its update stream. Throws when the
// map never gets initialised (no object detected: nothing to benchmark).
Recording recordUpdateStream(const ScenarioLog& log, const sonarfusion::MapperConfig& cfg);

// Applies stream.updates[0, count) (with their flags) to `map`, which must be
// initialised at stream.map_centre.
void replayStream(const UpdateStream& stream, std::size_t count, sonarfusion::VoxelMap& map);

// The libfusion view of a logged FLS frame (data_size 0 when the message's
// size disagreed, as the daemon refuses it).
sonarfusion::FlsFrame frameOf(const FlsMessage& m);

// Feeds one sonar message (in ScenarioLog order) to a Mapper; NAV too.
sonarfusion::Outcome feedEvent(const ScenarioLog& log, const ScenarioLog::Event& ev, sonarfusion::Mapper& mapper);

}  // namespace sfbench
