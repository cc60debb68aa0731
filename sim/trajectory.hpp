// The vehicle's sequences: one entry per simulator tick with its time, pose,
// PS head angle and whether an FLS frame is taken. Shared with the evaluator.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "scenario.hpp"
#include "sonarfusion/pose.hpp"

namespace sonarfusion::sim {

struct SequenceState {
    int64_t index = 0;   // global sequence number, 0-based
    int64_t utime = 0;   // us, strictly increasing
    int leg = 0;         // which pass (then which waypoint path) this belongs to
    Pose pose;           // vehicle in NED
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // NED, m/s
    double head_angle = 0.0;  // PS profiling angle phi_p of this sequence, rad
    bool has_fls = false;
};

// Sector scan: head_min -> head_max -> head_min ..., one step per sequence.
[[nodiscard]] double sectorScanAngle(const PsGeometry& ps, double step, int64_t index);

[[nodiscard]] std::vector<SequenceState> buildSequences(const Scenario& scenario);

}  // namespace sonarfusion::sim
