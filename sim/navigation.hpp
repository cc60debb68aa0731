// What the vehicle's navigation (NAV) reports against the true pose, per
// sequence: the scenario's `navigation` block (docs/navigation.md). Part of
// sf_scenario, so the evaluator can rebuild exactly the headings the mapper saw.
//
// For sequence i stamped t_i the NAV reports
//   truth(t_i - latency)                        (the true pose, lagged; motion included)
//   + drift_i + white position, depth noise     (position)
//   + heading_bias + white heading noise        (yaw, wrapped to [-pi, pi])
//   + white attitude noise                      (roll, pitch)
// where drift_i is a horizontal Gaussian random walk over the distance
// travelled (see NavigationModel). All random numbers come from the stream
// NoiseChannel::Nav of the scenario seed, eight per sequence, so enabling NAV
// errors changes neither the speckle nor the motion.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "scenario.hpp"
#include "sonarfusion/pose.hpp"
#include "trajectory.hpp"

namespace sonarfusion::sim {

struct NavReport {
    Pose truth;  // the true pose at utime - latency (the sequence's own pose when latency is 0)
    Eigen::Vector3d truth_velocity = Eigen::Vector3d::Zero();
    Pose reported;  // what the NAV message carries
    Eigen::Vector2d drift = Eigen::Vector2d::Zero();  // the random-walk part of the horizontal error
};

// The drift's random walk: per metre travelled each horizontal axis gains a
// variance of q = drift_fraction^2 * D / 2, D the planned path length of the
// whole scenario (legs plus the straight line between one leg's end and the
// next one's start, standing in for the turn-around); so after d metres the
// horizontal rms is drift_fraction * sqrt(D * d): drift_fraction * D at the end
// of the mission, more than drift_fraction * d before it.
[[nodiscard]] double plannedPathLength(const std::vector<SequenceState>& sequences);

// One report per sequence, in order. With an all-zero navigation block every
// report's truth and reported pose are the sequence's pose, bit for bit.
[[nodiscard]] std::vector<NavReport> reportNavigation(const Scenario& scenario,
                                                      const std::vector<SequenceState>& sequences);

// The true pose and velocity at `utime` on the leg of sequences[index], for a
// utime at or before that sequence's: interpolated between the leg's planned
// poses (linear position, shortest-arc heading), continued back along the
// leg's first velocity before the leg starts, then moved by the motion at utime.
void truePoseAt(const Scenario& scenario, const MotionModel& motion, const std::vector<SequenceState>& sequences,
                std::size_t index, int64_t utime, Pose& pose, Eigen::Vector3d& velocity);

}  // namespace sonarfusion::sim
