// The pipeline facade the daemon, the tools and the benchmarks drive: NAV, FLS
// and PS inputs in time order in, a voxel map and its objects out. All memory
// is allocated in the constructor; processing never allocates.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "sonarfusion/config.hpp"
#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/fls_update.hpp"
#include "sonarfusion/nav_buffer.hpp"
#include "sonarfusion/object_detector.hpp"
#include "sonarfusion/ps_carving.hpp"
#include "sonarfusion/ps_model.hpp"
#include "sonarfusion/segmentation.hpp"
#include "sonarfusion/state_codec.hpp"
#include "sonarfusion/track_axis.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

// What became of one input message. Used means it changed the pipeline state.
enum class Outcome : int {
    Used = 0,
    NavNonFinite,       // NaN/inf in the pose
    NavOutOfOrder,      // utime not after the previous NAV
    NoPose,             // no NAV brackets the message's utime
    NavGapTooLarge,     // the bracketing NAV samples are too far apart to interpolate
    FlsSizeMismatch,    // image size disagrees with the configured geometry or buffer
    FlsBeforeMap,       // no object detected yet: nothing to update
    FlsDisabled,        // the variant does not use the FLS
    PsEmpty,            // no bins
    PsBadGeometry,      // non-finite angle, bad range window
    PsNoEcho,           // no bin passed the selection rule
    NavTimeJump,        // NAV time jumped (ahead or back) beyond max_nav_gap_us: held until confirmed
    FlsBadGeometry,     // per-ping geometry not finite, not ordered, or outside the configured sonar's window/aperture
    FlsGeometryNotCached,  // fls.max_geometries 1: a geometry other than the configured one
    kCount
};
constexpr int kOutcomeCount = static_cast<int>(Outcome::kCount);
[[nodiscard]] std::string_view outcomeName(Outcome o);

struct MapperCounters {
    int64_t nav_in = 0, fls_in = 0, ps_in = 0;
    int64_t nav_used = 0, fls_used = 0, ps_used = 0;
    std::array<int64_t, kOutcomeCount> by_outcome{};
    int64_t fls_points_outside_map = 0;
    int64_t ps_endpoints_outside_map = 0;
    int64_t map_initialisations = 0;
    int64_t nav_timeline_resets = 0;  // confirmed NAV time jumps (clock steps, long dropouts)
    // Per-ping FLS geometry: direction tables computed for a geometry not cached,
    // and of those, how many replaced the least recently used one.
    int64_t fls_geometry_builds = 0;
    int64_t fls_geometry_evictions = 0;
    // Survey mode: what became of each detection, and of the maps.
    int64_t detections = 0;
    int64_t detection_in_active_map = 0;    // inside an active map: that map maps it
    int64_t detection_known_object = 0;     // on an object already published (its map no longer kept)
    int64_t detection_reopened_map = 0;     // inside a finalised map still kept: that map is reopened
    int64_t detection_no_free_map = 0;      // every slot busy: counted, nothing evicted
    int64_t maps_finalised = 0;
    int64_t objects_published = 0;
    int64_t objects_left_to_other_map = 0;  // a map that sees more of it publishes it
    int64_t objects_duplicate = 0;          // overlapped an object already published
    int64_t ps_pings_replayed = 0;          // held PS pings carved into a map when it was anchored
    int64_t fls_shadows = 0;                // FLS frames holding a shadow (DetectorConfig::fls_shadow_false_alarm)
    int64_t fls_frames_replayed = 0;        // held FLS frames applied to a map when it was anchored
    int64_t fls_frames_judged_later = 0;    // FLS frames judged with no seabed plane, judged again against one found later
};

// One slot of the survey pool. id 0: free.
struct MapSlot {
    int id = 0;
    bool leaving = false;  // the vehicle has left it: frozen, to be finalised
    int64_t updates = 0;   // FLS frames and PS pings that reached it
    // Finalised and published, kept until a new map needs the slot: a later
    // line that detects an object inside it reopens it (survey.reopen_on_revisit).
    bool parked = false;
    [[nodiscard]] bool inUse() const { return id != 0 && !parked; }  // being made (or left, not yet finalised)
};

class Mapper {
public:
    explicit Mapper(const MapperConfig& cfg);  // throws std::invalid_argument on a bad config

    // NAV in time order. A sample further than max_nav_gap_us from the newest
    // (either way) is held (NavTimeJump) until nav_timeline_confirm such samples,
    // each continuous with the last, confirm a new timeline; then the history is
    // replaced by them. A sample that continues the current timeline drops them.
    Outcome addNav(const TimedPose& nav);
    // Whether addNav(nav) would confirm a new timeline (and clear the history):
    // the daemon settles messages of the old timeline first.
    [[nodiscard]] bool navWouldReset(const TimedPose& nav) const;
    // NAV samples are held as a possible new timeline: sonar should wait.
    [[nodiscard]] bool navTimelinePending() const { return nav_candidate_count_ > 0; }
    [[nodiscard]] int navCandidateCount() const { return nav_candidate_count_; }
    [[nodiscard]] std::optional<int64_t> newestNavUtime() const;
    // The interpolated NAV pose at `utime`, as the sensor models would use it.
    [[nodiscard]] std::optional<Pose> navPoseAt(int64_t utime) const;
    Outcome addFls(const FlsFrame& frame);
    Outcome addPs(const PsPing& ping);
    // Paper 2.4 over the current map, the seabed averaged along the track axis
    // of the NAV received so far (see trackAxis()).
    const SegmentationStats& segment();
    // The same over the map of survey slot `slot`.
    const SegmentationStats& segmentSlot(int slot);

    // Survey mode (SurveyConfig). Slots are fixed at construction; map() is
    // slot 0's map (the first map anchored: the single-map mapper's map).
    [[nodiscard]] int slotCount() const { return static_cast<int>(maps_.size()); }
    [[nodiscard]] const VoxelMap& slotMap(int slot) const { return maps_[static_cast<std::size_t>(slot)]; }
    [[nodiscard]] const MapSlot& slot(int slot) const { return slots_[static_cast<std::size_t>(slot)]; }
    [[nodiscard]] int activeMaps() const;
    // A slot the vehicle has left (lowest map id first), -1 when none: the
    // caller finalises it (finaliseSlot), writes what it needs, then releases it.
    [[nodiscard]] int leavingSlot() const;
    // Marks every active map as left (shutdown, end of a log).
    void leaveAll();
    // Segments the slot's map and returns the objects it publishes (labels as
    // in segmenter()): an object is left to another active map that holds at
    // least as many occupied voxels inside its bounding box, and never
    // published twice (its box overlapping one already published). The
    // published boxes are remembered (SurveyConfig::published_capacity).
    const std::vector<ObjectInfo>& finaliseSlot(int slot);
    // Frees the slot for a new map. With survey.reopen_on_revisit the map stays
    // in it, parked (MapSlot::parked), until a new map needs the slot (the
    // oldest parked map goes first) or a later detection inside it reopens it;
    // a reopened map is finalised again and republishes its objects.
    void releaseSlot(int slot);

    // Checkpoints: everything the pipeline needs to go on (map, detector, NAV
    // history and held samples, track axis, counters). loadState needs a Mapper
    // built from the same config; false (state unspecified: rebuild it) on any
    // mismatch or damage.
    void saveState(StateWriter& w) const;
    [[nodiscard]] bool loadState(StateReader& r);
    // An upper bound of saveState's size, for sizing the buffer once.
    [[nodiscard]] std::size_t stateBytesBound() const;

    // Anchors a map by hand (e.g. a known target) in the first free slot (or
    // the oldest parked one); counted as detection_no_free_map when there is none.
    void initialiseMapAt(const Eigen::Vector3d& centre);

    [[nodiscard]] const VoxelMap& map() const { return maps_.front(); }
    [[nodiscard]] VoxelMap& mutableMap() { return maps_.front(); }
    [[nodiscard]] const Segmenter& segmenter() const { return segmenter_; }
    [[nodiscard]] const ObjectDetector& detector() const { return detector_; }
    [[nodiscard]] const TrackAxis& trackAxis() const { return track_axis_; }
    [[nodiscard]] const MapperCounters& counters() const { return counters_; }
    [[nodiscard]] const MapperConfig& config() const { return cfg_; }
    // The configured FLS geometry (frames without their own geometry use it).
    [[nodiscard]] const FlsModel& flsModel() const { return fls_model_; }
    // Per-ping geometry cache: slot 0 is the configured geometry; slots
    // 1..fls.max_geometries-1 hold other geometries (flsGeometryModel(i) for
    // i >= 1), empty until a frame needs one. Which slot the last used frame went to.
    [[nodiscard]] int flsGeometrySlots() const { return fls_updater_.geometries(); }
    [[nodiscard]] bool flsGeometryCached(int slot) const { return slot == 0 || fls_geometry_used_[static_cast<std::size_t>(slot)] != 0; }
    [[nodiscard]] const FlsModel& flsGeometryModel(int slot) const {
        return slot == 0 ? fls_model_ : fls_models_[static_cast<std::size_t>(slot) - 1];
    }
    [[nodiscard]] int lastFlsGeometrySlot() const { return fls_updater_.selected(); }
    // The seabed plane the last FLS frame's votes were judged against (none before the detector has one).
    // The seabed plane the last FLS frame's votes were (or, before any map, would have been) judged against.
    [[nodiscard]] const std::optional<SeabedFit>& lastFlsSeabed() const { return last_fls_seabed_; }
    [[nodiscard]] const PsModel& psModel() const { return ps_model_; }

private:
    Outcome count(Outcome o);
    Outcome lookupPose(int64_t utime, Pose& out) const;
    void onDetection(const Eigen::Vector3d& at);
    // Per-ping FLS geometry: Used when the frame's own geometry is sane.
    [[nodiscard]] Outcome checkFlsGeometry(const FlsFrame& frame) const;
    // The cache slot holding the frame's geometry, filled (LRU) when absent;
    // -1 none (max_geometries 1), -2 it did not fit (bad geometry).
    int flsGeometrySlot(const FlsFrame& frame);
    void markLeftMaps(const Eigen::Vector3d& vehicle);
    // Whether a sensor at `p` with this maximum range can reach the slot's map.
    [[nodiscard]] bool reaches(int slot, const Eigen::Vector3d& p, double range) const;
    [[nodiscard]] bool updatable(int slot) const { return slots_[slot].inUse() && !slots_[slot].leaving; }
    // A slot for a new map: the first free one, else the oldest parked one
    // (released here); -1 when every slot holds a map being made.
    int slotForNewMap();

    // One PS ping as carving uses it, held (DetectorConfig::replay_pings) for a
    // map the detector anchors later.
    struct HeldPing {
        Eigen::Isometry3d world_from_sensor = Eigen::Isometry3d::Identity();
        double head_angle = 0.0, range = 0.0, strength = 0.0, carve_range = -1.0, range_max = 0.0;
    };
    // Carves the held pings, oldest first, into the slot's new map.
    void replayHeldPings(int slot);
    // A PS echo at `range` on the beam at `head`, placed on the beam's centre,
    // and how much deeper the same echo may lie across the fan's thickness, on
    // its steepest edge (DetectorConfig::rise_from_deepest_in_beam).
    struct FanEcho {
        Eigen::Vector3d at;
        double deeper_by;
    };
    [[nodiscard]] FanEcho fanEcho(const Eigen::Isometry3d& world_from_sensor, double range, double head) const;
    // Whether the PS sector's near edge (its steepest ray, from the newest held
    // ping's pose, along its look) has come within cluster_radius of `object`
    // or past it: this pass's PS looks no more at the object's near part
    // (DetectorConfig::replay_risen_pings_whole).
    [[nodiscard]] bool psSectorHasPassed(const Eigen::Vector3d& object) const;
    [[nodiscard]] bool loadHeldPings(StateReader& r);
    void holdFrame(const FlsFrame& frame, const Eigen::Isometry3d& world_from_sensor,
                   const std::optional<SeabedFit>& seabed);
    void replayHeldFrames(int slot);
    // Awaiting frames judged per incoming FLS frame: each walks only the arcs
    // of its pixels the seabed cannot explain (FlsUpdater::applyAboveSeabedVotes),
    // up to a whole frame's update when they are many, so a backlog (up to
    // replay_fls_frames) drains over frames instead of in one; more than one per frame, and oldest first, so the ring, which
    // reuses one slot per frame, never takes one before it is judged.
    static constexpr int kAwaitingJudgedPerFrame = 2;
    void judgeAwaitingFrames(int budget);
    struct HeldFrame;
    void awaitSeabed(HeldFrame& h, int slot);
    [[nodiscard]] FlsFrame heldFrameImage(int index, std::size_t pixels) const;
    [[nodiscard]] bool judgesLater() const {
        return cfg_.update.fls_seabed_at_footprint && cfg_.update.fls_seabed_judged_later;
    }
    [[nodiscard]] static Eigen::Vector3d flsBoresight(const FlsModel& model, const Eigen::Isometry3d& world_from_sensor);
    void saveHeldFrames(StateWriter& w) const;
    [[nodiscard]] bool loadHeldFrames(StateReader& r);

    struct Box {
        Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
        int map_id = 0;  // the map that published it
    };

    MapperConfig cfg_;
    std::vector<VoxelMap> maps_;  // one per survey slot, all allocated here
    std::vector<MapSlot> slots_;
    int next_map_id_ = 1;
    double release_margin_ = 0.0;
    std::vector<Box> published_;  // ring of published objects' bounding boxes
    int published_count_ = 0, published_next_ = 0;
    std::vector<ObjectInfo> finalised_;  // capacity max_objects
    FlsModel fls_model_;
    PsModel ps_model_;
    FlsUpdater fls_updater_;
    std::vector<FlsModel> fls_models_;        // geometry slots 1.. (index slot - 1), allocated here
    std::vector<int64_t> fls_geometry_used_;  // per slot: last use (tick), 0 = empty
    int64_t fls_geometry_tick_ = 0;
    PsCarver ps_carver_;
    std::vector<HeldPing> held_pings_;  // ring, DetectorConfig::replay_pings
    int held_count_ = 0, held_next_ = 0;
    // DetectorConfig::replay_fls_frames: a held FLS frame (its image in held_pixels_).
    struct HeldFrame {
        int64_t utime = 0;
        Eigen::Isometry3d world_from_sensor = Eigen::Isometry3d::Identity();
        std::optional<SeabedFit> seabed;  // the plane its votes were judged against
        int awaiting_map = 0;  // id of the map whose above-seabed votes it still owes, once a plane exists (0: none)
    };
    std::vector<HeldFrame> held_frames_;  // ring
    std::vector<uint8_t> held_pixels_;    // rows x cols per held frame, allocated here
    int held_frame_count_ = 0, held_frame_next_ = 0;
    int awaiting_frames_ = 0;  // held frames with awaiting_map set
    std::optional<SeabedFit> last_fls_seabed_;
    ObjectDetector detector_;
    Segmenter segmenter_;
    NavBuffer nav_;
    std::array<TimedPose, kMaxNavTimelineConfirm> nav_candidate_{};
    int nav_candidate_count_ = 0;
    TrackAxis track_axis_;
    MapperCounters counters_;
};

// MapperConfig::validate() as one message naming the key ("map.nx: must be in
// 1..4096"); an empty string when the config is fine. The constructor throws
// std::invalid_argument with the same message.
[[nodiscard]] std::string validateConfig(const MapperConfig& cfg);
// What a Mapper built from `cfg` allocates, in bytes (an upper estimate), so a
// program can refuse a config that would not fit before allocating anything.
[[nodiscard]] std::size_t estimatedMemoryBytes(const MapperConfig& cfg);

}  // namespace sonarfusion
