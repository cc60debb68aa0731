#include "navigation.hpp"

#include <algorithm>
#include <cmath>

#include "random.hpp"

namespace sonarfusion::sim {

double plannedPathLength(const std::vector<SequenceState>& sequences) {
    double length = 0.0;
    for (std::size_t i = 1; i < sequences.size(); ++i)
        length += (sequences[i].planned.position - sequences[i - 1].planned.position).norm();
    return length;
}

void truePoseAt(const Scenario& scenario, const MotionModel& motion, const std::vector<SequenceState>& sequences,
                std::size_t index, int64_t utime, Pose& pose, Eigen::Vector3d& velocity) {
    const SequenceState& q = sequences[index];
    std::size_t first = index;
    while (first > 0 && sequences[first - 1].leg == q.leg) --first;
    Pose planned;
    Eigen::Vector3d planned_velocity;
    if (utime >= q.utime) {
        planned = q.planned;
        planned_velocity = q.planned_velocity;
    } else if (utime <= sequences[first].utime) {
        // Before the leg starts: the vehicle was already flying in along it.
        const SequenceState& a = sequences[first];
        planned = a.planned;
        planned.position += a.planned_velocity * (static_cast<double>(utime - a.utime) * 1e-6);
        planned_velocity = a.planned_velocity;
    } else {
        // Last sequence of the leg at or before utime; the next one is after it.
        const auto begin = sequences.begin() + static_cast<std::ptrdiff_t>(first);
        const auto end = sequences.begin() + static_cast<std::ptrdiff_t>(index) + 1;
        const auto after = std::upper_bound(begin, end, utime,
                                            [](int64_t u, const SequenceState& s) { return u < s.utime; });
        const SequenceState& a = *(after - 1);
        const SequenceState& b = *after;
        planned = interpolate(TimedPose{a.utime, a.planned}, TimedPose{b.utime, b.planned}, utime);
        planned_velocity = a.planned_velocity;
    }
    const double t = static_cast<double>(utime - scenario.trajectory.start_utime) * 1e-6;
    pose = motion.apply(planned, t);
    velocity = motion.applyVelocity(planned_velocity, t);
}

std::vector<NavReport> reportNavigation(const Scenario& scenario, const std::vector<SequenceState>& sequences) {
    std::vector<NavReport> out(sequences.size());
    const NavigationSpec& n = scenario.navigation;
    if (!n.enabled()) {
        for (std::size_t i = 0; i < sequences.size(); ++i) {
            out[i].truth = out[i].reported = sequences[i].pose;
            out[i].truth_velocity = sequences[i].velocity;
        }
        return out;
    }
    const MotionModel motion(scenario.motion, scenario.seed);
    const int64_t latency_us = std::llround(n.latency * 1e6);
    // Per-metre variance of each horizontal axis of the random walk.
    const double per_metre_variance = 0.5 * n.drift_fraction * n.drift_fraction * plannedPathLength(sequences);
    Eigen::Vector2d drift = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < sequences.size(); ++i) {
        const SequenceState& q = sequences[i];
        NavReport& r = out[i];
        if (latency_us == 0) {
            r.truth = q.pose;
            r.truth_velocity = q.velocity;
        } else {
            truePoseAt(scenario, motion, sequences, i, q.utime - latency_us, r.truth, r.truth_velocity);
        }
        // Eight numbers per sequence in a fixed order, whichever errors are on.
        Rng rng(noiseSeed(scenario.seed, NoiseChannel::Nav, q.index, 0));
        double g[8];
        for (double& v : g) v = rng.gaussian();
        if (i > 0) {
            const double step = (q.planned.position - sequences[i - 1].planned.position).norm();
            drift += std::sqrt(per_metre_variance * step) * Eigen::Vector2d(g[6], g[7]);
        }
        r.drift = drift;
        Pose& p = r.reported;
        p = r.truth;
        p.position.x() += drift.x() + n.position_noise * g[0];
        p.position.y() += drift.y() + n.position_noise * g[1];
        p.position.z() += n.depth_noise * g[2];
        p.yaw = std::remainder(r.truth.yaw + n.heading_bias + n.heading_noise * g[3], 2.0 * M_PI);
        p.roll += n.attitude_noise * g[4];
        p.pitch += n.attitude_noise * g[5];
    }
    return out;
}

}  // namespace sonarfusion::sim
