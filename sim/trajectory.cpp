#include "trajectory.hpp"

#include <algorithm>
#include <cmath>

#include "random.hpp"

namespace sonarfusion::sim {

double sectorScanAngle(const PsGeometry& ps, double step, int64_t index) {
    const double span = ps.head_max - ps.head_min;
    const int64_t steps = std::max<int64_t>(1, std::llround(span / step));
    if (span <= 0.0) return ps.head_min;
    const int64_t phase = index % (2 * steps);
    const int64_t position = phase <= steps ? phase : 2 * steps - phase;
    return ps.head_min + span * static_cast<double>(position) / static_cast<double>(steps);
}

MotionModel::MotionModel(const MotionSpec& spec, uint64_t seed) : spec_(spec) {
    for (uint32_t axis = 0; axis < 4; ++axis) {
        Rng rng(noiseSeed(seed, NoiseChannel::Motion, 0, axis));
        phase_[axis] = 2.0 * M_PI * rng.uniform();
    }
}

MotionModel::Offsets MotionModel::at(double t) const {
    Offsets o;
    if (!spec_.enabled()) return o;
    const double w = 2.0 * M_PI / spec_.period;
    o.roll = spec_.roll_amplitude * std::sin(w * t + phase_[0]);
    o.pitch = spec_.pitch_amplitude * std::sin(w * t + phase_[1]);
    o.yaw = spec_.yaw_amplitude * std::sin(w * t + phase_[2]);
    o.heave = spec_.heave_amplitude * std::sin(w * t + phase_[3]);
    o.heave_rate = spec_.heave_amplitude * w * std::cos(w * t + phase_[3]);
    return o;
}

Pose MotionModel::apply(const Pose& planned, double t) const {
    if (!spec_.enabled()) return planned;
    const Offsets o = at(t);
    Pose p = planned;
    p.roll += o.roll;
    p.pitch += o.pitch;
    p.yaw = std::remainder(planned.yaw + o.yaw, 2.0 * M_PI);
    p.position.z() += o.heave;
    return p;
}

Eigen::Vector3d MotionModel::applyVelocity(const Eigen::Vector3d& planned, double t) const {
    if (!spec_.enabled()) return planned;
    return planned + Eigen::Vector3d(0.0, 0.0, at(t).heave_rate);
}

namespace {

struct Builder {
    const Scenario& s;
    MotionModel motion;
    std::vector<SequenceState> out;
    int64_t period_us;
    int64_t next_utime;

    void add(int leg, const Eigen::Vector3d& position, double heading, const Eigen::Vector3d& velocity) {
        SequenceState q;
        q.index = static_cast<int64_t>(out.size());
        q.utime = next_utime;
        q.leg = leg;
        q.planned.position = position;
        q.planned.yaw = heading;
        q.planned_velocity = velocity;
        const double t = static_cast<double>(q.utime - s.trajectory.start_utime) * 1e-6;
        q.pose = motion.apply(q.planned, t);
        q.velocity = motion.applyVelocity(velocity, t);
        q.head_angle = sectorScanAngle(s.ps, s.ps_sim.head_step, q.index);
        q.has_fls = q.index % s.trajectory.fls_every == 0;
        out.push_back(q);
        next_utime += period_us;
    }
    void endLeg() { next_utime += std::llround(s.trajectory.pass_gap * 1e6); }
};

}  // namespace

std::vector<SequenceState> buildSequences(const Scenario& s) {
    const TrajectorySpec& t = s.trajectory;
    Builder b{s, MotionModel(s.motion, s.seed), {}, std::max<int64_t>(1, std::llround(t.sequence_period * 1e6)), t.start_utime};
    int leg = 0;
    for (const StraightPass& p : t.passes) {
        const Eigen::Vector3d dir(std::cos(p.heading), std::sin(p.heading), 0.0);
        const Eigen::Vector3d centre(p.centre_x, p.centre_y, s.scene.seabed_depth - p.altitude);
        const Eigen::Vector3d velocity = dir * (p.step / t.sequence_period);
        for (int k = 0; k < p.sequences; ++k) b.add(leg, centre + (k * p.step - p.start_offset) * dir, p.heading, velocity);
        b.endLeg();
        ++leg;
    }
    for (const WaypointPath& w : t.waypoints) {
        // Walk the polyline at a fixed arc-length step; heading follows the segment.
        double carried = 0.0;  // arc length already walked into the current segment
        for (std::size_t i = 0; i + 1 < w.points.size(); ++i) {
            const Eigen::Vector3d a(w.points[i][0], w.points[i][1], w.points[i][2]);
            const Eigen::Vector3d c(w.points[i + 1][0], w.points[i + 1][1], w.points[i + 1][2]);
            const double length = (c - a).norm();
            if (length <= 0.0) continue;
            const Eigen::Vector3d dir = (c - a) / length;
            const double heading = std::atan2(dir.y(), dir.x());
            double along = carried;
            for (; along < length; along += w.step) b.add(leg, a + along * dir, heading, dir * (w.step / t.sequence_period));
            carried = along - length;
        }
        b.endLeg();
        ++leg;
    }
    return b.out;
}

}  // namespace sonarfusion::sim
