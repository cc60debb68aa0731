// The vehicle's sequences: one entry per simulator tick with its time, true
// pose, PS head angle and whether an FLS frame is taken. Shared with the
// evaluator. The true pose is the planned path plus the scenario's `motion`
// (docs/navigation.md); what NAV reports about it is in navigation.hpp.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "scenario.hpp"
#include "sonarfusion/pose.hpp"

namespace sonarfusion::sim {

struct SequenceState {
    int64_t index = 0;   // global sequence number, 0-based
    int64_t utime = 0;   // us, strictly increasing
    int leg = 0;         // which pass (then which waypoint path) this belongs to
    Pose pose;           // true vehicle pose in NED: `planned` plus the motion
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // true NED velocity, m/s (planned plus heave rate)
    Pose planned;        // on the planned path: level, heading of the leg or segment
    Eigen::Vector3d planned_velocity = Eigen::Vector3d::Zero();
    double head_angle = 0.0;  // PS profiling angle phi_p of this sequence, rad
    bool has_fls = false;
};

// Sector scan: head_min -> head_max -> head_min ..., one step per sequence.
[[nodiscard]] double sectorScanAngle(const PsGeometry& ps, double step, int64_t index);

// The vehicle's attitude and depth offsets from the planned path at a time:
// each axis a * sin(2 pi t / period + phase), its phase uniform in [0, 2 pi)
// from the scenario seed (stream NoiseChannel::Motion, index = axis).
class MotionModel {
public:
    MotionModel(const MotionSpec& spec, uint64_t seed);
    struct Offsets {
        double roll = 0, pitch = 0, yaw = 0, heave = 0;  // rad, rad, rad, m (NED z)
        double heave_rate = 0;                            // m/s
    };
    // t: seconds since the scenario's start_utime.
    [[nodiscard]] Offsets at(double t) const;
    // `planned` moved by the offsets at t (the planned pose itself when the
    // motion is all zero).
    [[nodiscard]] Pose apply(const Pose& planned, double t) const;
    [[nodiscard]] Eigen::Vector3d applyVelocity(const Eigen::Vector3d& planned, double t) const;
    [[nodiscard]] const std::array<double, 4>& phases() const { return phase_; }  // roll, pitch, yaw, heave

private:
    MotionSpec spec_;
    std::array<double, 4> phase_{};
};

[[nodiscard]] std::vector<SequenceState> buildSequences(const Scenario& scenario);

}  // namespace sonarfusion::sim
