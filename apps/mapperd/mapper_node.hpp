// The daemon's core, shared by the live LCM loop and the offline log reader:
// raw message bytes in (after the guard), deterministic ordering against NAV,
// libfusion, counters and timing out. No LCM instance inside: output goes
// through a callback so tests and offline mode need no network.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/map_snapshot_t.hpp>
#include <sonarfusion/mapper_status_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/objects_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

#include "mapper_config_yaml.hpp"
#include "message_guard.hpp"
#include "sonarfusion/mapper.hpp"

namespace sonarfusion {

// Reasons the daemon rejects a message before libfusion sees it.
enum class TransportReject : int {
    Malformed = 0,        // passed the guard but lcm-gen's decode refused it
    FlsGeometryMismatch,  // tilt or mounting disagree with the config (ranges, bearings, aperture: libfusion's fls_bad_geometry)
    Stale,                // older than a message of its channel already processed (out of order)
    PendingOverflow,      // all waiting slots taken: one waiting message was thinned out
    PsGeometryMismatch,   // fan, tilt, mounting, range window or head angle outside the configured sonar
    BadFingerprint,       // guard verdicts, before decode (message_guard.hpp)
    Truncated,
    TrailingBytes,
    BadCount,             // a negative array count, or one beyond the configured sonar
    Duplicate,            // the same (utime, seq) as a message processed or waiting
    kCount
};

// A survey map the vehicle has left (or every map at the end), segmented,
// with the objects it publishes (labels as in segmenter.objectLabel).
struct FinalisedMap {
    int map_id;
    const VoxelMap& map;
    const Segmenter& segmenter;
    const std::vector<ObjectInfo>& objects;
};

class MapperNode {
public:
    struct Publisher {
        std::function<void(const mapper_status_t&)> status;
        std::function<void(const objects_t&)> objects;
        std::function<void(const map_snapshot_t&)> map;
        // Called every daemon.checkpoint_period_s of accepted NAV time (if set).
        std::function<void()> checkpoint;
        // Called once per finalised map, before its slot is freed (writes its files).
        std::function<void(const FinalisedMap&)> finalised;
    };

    MapperNode(const DaemonConfig& cfg, Publisher out);

    // One raw message from `channel`; unknown channels are ignored.
    void handle(const std::string& channel, const void* data, std::size_t size);
    // Processes every pending sonar message that NAV now brackets; with
    // `force`, also those still waiting (end of a log, or a NAV timeout).
    void flush(bool force);
    // Sonar slots the daemon holds (for tests and the checkpoint).
    [[nodiscard]] int pendingCount() const;
    // Called periodically in live mode: releases messages that waited too long.
    void tick(int64_t now_wall_us);

    // Segments every map being made and publishes its objects (one OBJECTS
    // message per map).
    void segmentAndPublish();
    void publishStatus();
    // Finalises every map the vehicle has left: segment, publish its objects,
    // hand it to Publisher::finalised, free its slot.
    void finaliseLeftMaps();
    // End of the run (after the last flush): every map is finalised.
    void finish();

    // Checkpoints (checkpoint.hpp): the pipeline, the waiting sonar messages,
    // the counters and sequence state. loadState needs a node built from the
    // same config; false on any mismatch (then discard the node).
    void saveState(StateWriter& w) const;
    [[nodiscard]] bool loadState(StateReader& r);
    [[nodiscard]] std::size_t stateBytesBound() const;
    // Offline runs: how many log events a checkpoint taken now has consumed, so
    // a resumed run skips exactly those.
    void setInputPosition(int64_t events) { input_position_ = events; }
    [[nodiscard]] int64_t inputPosition() const { return input_position_; }

    [[nodiscard]] const Mapper& mapper() const { return mapper_; }
    [[nodiscard]] const DaemonConfig& config() const { return cfg_; }
    [[nodiscard]] int64_t seqGaps(int channel) const { return gaps_[channel]; }
    [[nodiscard]] int64_t transportRejects(TransportReject r) const { return rejects_[static_cast<int>(r)]; }
    // Everything refused as bytes: the guard's four verdicts and failed decodes.
    [[nodiscard]] int64_t refusedBytes() const;
    [[nodiscard]] double p99Us() const;
    [[nodiscard]] double maxUs() const { return proc_max_us_; }
    // The status message, refreshed in place (no allocation after start-up).
    [[nodiscard]] const mapper_status_t& status();

private:
    // A sonar message waiting for NAV to bracket it, decoded in place.
    template <class Msg>
    struct Pending {
        Msg msg;
        bool used = false;
        int64_t arrival_wall_us = 0;
        int64_t nav_epoch = 0;  // which NAV timeline was current when it arrived
    };
    using PendingFls = Pending<fls_image_t>;
    using PendingPs = Pending<ps_ping_t>;

    // Guard verdict, free slot (flushing if all are taken), decode, seq tracking.
    template <class Msg>
    void enqueue(std::vector<Pending<Msg>>& slots, guard::Verdict verdict, int channel, const void* data,
                 std::size_t size);
    void countRefusal(guard::Verdict v);
    // Processes waiting messages in order; `before_epoch` limits it to those that
    // arrived before that NAV timeline began.
    void flushOrdered(bool force, int64_t before_epoch);

    void onNav(const void* data, std::size_t size);
    void onFls(const void* data, std::size_t size);
    void onPs(const void* data, std::size_t size);
    void processFls(fls_image_t& m);
    void processPs(ps_ping_t& m);
    bool flsGeometryMatches(const fls_image_t& m) const;
    bool psGeometryMatches(const ps_ping_t& m) const;
    void trackSeq(int channel, int64_t seq);
    void recordTime(std::chrono::steady_clock::time_point start);
    void maybePeriodic(int64_t data_utime);
    void publishObjects(int map_id, const std::vector<ObjectInfo>& objects);

    DaemonConfig cfg_;
    Publisher out_;
    Mapper mapper_;
    std::string variant_;
    nav_state_t nav_msg_;
    std::vector<PendingFls> fls_pending_;  // fixed slots, decoded into in place
    std::vector<PendingPs> ps_pending_;
    std::array<int64_t, 3> last_seq_{{-1, -1, -1}};
    std::array<int64_t, 3> gaps_{};
    // The last processed (utime, seq) per sonar channel: older arrivals are stale.
    std::array<int64_t, 3> done_utime_{{INT64_MIN, INT64_MIN, INT64_MIN}};
    std::array<int64_t, 3> done_seq_{{INT64_MIN, INT64_MIN, INT64_MIN}};
    std::array<int64_t, static_cast<int>(TransportReject::kCount)> rejects_{};
    int64_t newest_nav_utime_ = INT64_MIN;
    int64_t nav_epoch_ = 0;
    guard::Limits limits_;
    std::vector<double> proc_us_;  // ring of recent processing times
    mutable std::vector<double> scratch_;
    std::size_t proc_count_ = 0;
    double proc_last_us_ = 0.0, proc_max_us_ = 0.0;
    int64_t overruns_ = 0;
    int64_t status_seq_ = 0, objects_seq_ = 0, map_seq_ = 0;
    int64_t last_status_utime_ = INT64_MIN, last_segment_utime_ = INT64_MIN, last_map_utime_ = INT64_MIN;
    int64_t newest_data_utime_ = 0;
    int64_t last_checkpoint_utime_ = INT64_MIN;
    int64_t input_position_ = 0;
    // The first map's place, for MAPPER_STATUS (kept after it is finalised).
    Eigen::Vector3d first_origin_ = Eigen::Vector3d::Zero(), first_centre_ = Eigen::Vector3d::Zero();
    // Outgoing messages, sized at start-up and refilled in place.
    mapper_status_t status_msg_;
    objects_t objects_msg_;
    map_snapshot_t snapshot_msg_;
};

}  // namespace sonarfusion
