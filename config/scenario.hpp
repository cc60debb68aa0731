// A simulation scenario as loaded from YAML (docs/scenario-format.md): scene
// meshes, sensor geometry and mounting, trajectory, noise and seed. Part of
// the shared config reader (sf_config_yaml): the simulator and the evaluator
// read scenarios only through loadScenario, and its sensor blocks through the
// same functions as the mapper config (config_yaml.hpp). Each struct checks
// its own values (validate(), keys relative to its block, as in config.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sonarfusion/config.hpp"

namespace sonarfusion::sim {

// Thrown for any bad scenario input; what() names the offending field,
// e.g. "scenario field 'fls.range_max': must be above range_min and <= 1000 m".
class ScenarioError : public std::runtime_error {
public:
    ScenarioError(const std::string& field, const std::string& problem)
        : std::runtime_error("scenario field '" + field + "': " + problem), field_(field) {}
    [[nodiscard]] const std::string& field() const { return field_; }

private:
    std::string field_;
};

enum class MeshRole { Seabed, Object };

struct MeshSpec {
    std::string path;           // absolute, or relative to the scenario file when loaded
    MeshRole role = MeshRole::Object;
    double impedance = 8.0;     // MRayl (acoustic impedance Z of the material)
    double face_angle_deg = 0;  // true end-face angle alpha of an object, 0 when not given
    // Where the file's vertices go (docs/scenario-format.md): world =
    // position + R(roll, pitch, yaw) * (scale * vertex), R as a vehicle's
    // attitude (Pose::rotation, Z-Y-X). The defaults leave the file as it is.
    double scale = 1.0;                          // file units to metres
    std::array<double, 3> position{0, 0, 0};     // m, NED world
    std::array<double, 3> rotation{0, 0, 0};     // rad: roll, pitch, yaw (rpy_deg in the file)
    [[nodiscard]] Eigen::Isometry3d pose() const;  // the rotation, then the translation
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `scene.meshes[i]` block
};

struct SceneSpec {
    std::vector<MeshSpec> meshes;
    double water_impedance = 1.5;  // MRayl, Z0
    double seabed_depth = 20.0;    // m (NED z), turns pass altitudes into depths
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `scene` block
};

// An operator's range setting: from sequence `at_sequence` on (global sequence
// index, as trajectory.fls_every counts it), FLS frames cover range_min..range_max
// with the same rows and beams (docs/scenario-format.md, `fls.window_changes`).
struct FlsWindowChange {
    int64_t at_sequence = 0;
    double range_min = 0.0, range_max = 0.0;  // m
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of one `fls.window_changes[i]` entry
};

// Simulator-only parameters of the FLS beyond the mapper's FlsGeometry.
struct FlsSimParams {
    std::string name = "DIDSON";
    int rays_azimuth = 4;      // rays across one beam's azimuth width
    int rays_elevation = 256;  // rays across the vertical aperture
    double gain_db = 0.0;      // extra gain on top of the calibrated default
    double tvg_db_per_decade = 40.0;  // 40 log R undoes two-way spreading
    double source_level = 1.0;        // I0
    double sound_speed = 1500.0;      // m/s (informational, in the message)
    double frequency_hz = 1.8e6;
    std::vector<FlsWindowChange> window_changes;  // in increasing at_sequence; empty: the window never changes
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `fls` block
};

struct PsSimParams {
    std::string name = "881A";
    double head_step = 0.9 * kDegToRad;         // rad per sequence of the sector scan
    double beam_width_vertical = 2.0 * kDegToRad;  // rad, the fan's thin direction
    int rays_fan = 64;        // rays across the horizontal fan
    int rays_vertical = 5;    // rays across the vertical beam width
    double gain_db = 0.0;
    double tvg_db_per_decade = 40.0;
    double source_level = 1.0;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `ps` block
};

struct NoiseSpec {
    bool speckle = true;
    int scatterers = 8;              // random-phase scatterers per pixel
    double coherent_fraction = 0.2;  // share of the echo power that is coherent (no speckle)
    double floor = 10.0;             // rms of the additive water noise, in 8-bit counts
    // Draw the noise from the sensor pose (and PS head angle) instead of the
    // sequence number: a vehicle holding still then sees the same speckle.
    bool follows_pose = false;
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `noise` block
};

struct StraightPass {
    double heading = 0.0;       // rad, 0 = north
    double altitude = 3.12;     // m above scene.seabed_depth
    double step = 0.005;        // m per sequence
    int sequences = 1600;
    double start_offset = 6.0;  // m before the centre point, along the heading
    double centre_x = 0.0, centre_y = 0.0;  // NED point the pass flies over
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `trajectory.passes[i]` block
};

struct WaypointPath {
    double step = 0.005;  // m per sequence along the polyline
    std::vector<std::array<double, 3>> points;  // NED x, y, z
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `trajectory.waypoints[i]` block
};

struct TrajectorySpec {
    double sequence_period = 0.05;     // s between sequences
    int64_t start_utime = 1700000000000000;  // us of the first sequence
    double pass_gap = 5.0;             // s of silence between legs (turn-around)
    int fls_every = 4;                 // an FLS frame every Nth sequence
    std::vector<StraightPass> passes;
    std::vector<WaypointPath> waypoints;  // flown after the passes
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `trajectory` block
};

// What NAV reports against the true pose (docs/navigation.md). All zero: NAV is
// the truth, as before this block existed.
struct NavigationSpec {
    double position_noise = 0.0;  // m rms, white, per horizontal axis
    double depth_noise = 0.0;     // m rms, white
    double drift_fraction = 0.0;  // horizontal random-walk drift: rms = fraction x mission distance at its end
    double heading_bias = 0.0;    // rad, constant
    double heading_noise = 0.0;   // rad rms, white
    double attitude_noise = 0.0;  // rad rms, white, on roll and on pitch
    double latency = 0.0;         // s: NAV stamped t reports the true pose at t - latency
    [[nodiscard]] bool enabled() const {
        return position_noise != 0.0 || depth_noise != 0.0 || drift_fraction != 0.0 || heading_bias != 0.0 ||
               heading_noise != 0.0 || attitude_noise != 0.0 || latency != 0.0;
    }
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `navigation` block
};

// The true vehicle motion about the planned path: a sinusoid per axis, one
// period, each axis with its own phase drawn from the seed.
struct MotionSpec {
    double roll_amplitude = 0.0;   // rad
    double pitch_amplitude = 0.0;  // rad
    double yaw_amplitude = 0.0;    // rad
    double heave_amplitude = 0.0;  // m (NED z)
    double period = 0.0;           // s
    [[nodiscard]] bool enabled() const {
        return roll_amplitude != 0.0 || pitch_amplitude != 0.0 || yaw_amplitude != 0.0 || heave_amplitude != 0.0;
    }
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `motion` block
};

struct Channels {
    std::string nav = "NAV", fls = "FLS", ps = "PS";
    // The true pose (nav_state_t), published only when the scenario's
    // navigation or motion block is not all zero.
    std::string nav_truth = "NAV_TRUTH";
    [[nodiscard]] std::optional<ConfigIssue> validate() const;  // keys of the `channels` block
};

struct Scenario {
    std::string name;
    std::string source_path;  // the YAML file, empty when loaded from a string
    SceneSpec scene;
    FlsGeometry fls;
    PsGeometry ps;
    Mounting fls_mount, ps_mount;
    FlsSimParams fls_sim;
    PsSimParams ps_sim;
    NoiseSpec noise;
    NavigationSpec navigation;
    MotionSpec motion;
    TrajectorySpec trajectory;
    Channels channels;
    uint64_t seed = 1;

    // The end-face angle of the first object mesh that declares one (deg), or 0.
    [[nodiscard]] double trueFaceAngleDeg() const;
    // NAV differs from the truth, or the vehicle moves off its planned attitude
    // and depth: the simulator then also publishes the truth (channels.nav_truth).
    [[nodiscard]] bool publishesTruth() const { return navigation.enabled() || motion.enabled(); }
    // Every block, keys in full ("fls.rays_azimuth"); cross-block rules (channels.nav_truth).
    [[nodiscard]] std::optional<ConfigIssue> validate() const;
};

// Loads and validates a scenario. Mesh paths are resolved relative to the
// file's folder and must exist. Throws ScenarioError naming the field.
[[nodiscard]] Scenario loadScenario(const std::string& path);
// Same from YAML text; relative mesh paths resolve against base_dir.
[[nodiscard]] Scenario loadScenarioFromString(const std::string& yaml, const std::string& base_dir);

}  // namespace sonarfusion::sim
