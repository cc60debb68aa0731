#include "trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace sonarfusion::sim {

double sectorScanAngle(const PsGeometry& ps, double step, int64_t index) {
    const double span = ps.head_max - ps.head_min;
    const int64_t steps = std::max<int64_t>(1, std::llround(span / step));
    if (span <= 0.0) return ps.head_min;
    const int64_t phase = index % (2 * steps);
    const int64_t position = phase <= steps ? phase : 2 * steps - phase;
    return ps.head_min + span * static_cast<double>(position) / static_cast<double>(steps);
}

namespace {

struct Builder {
    const Scenario& s;
    std::vector<SequenceState> out;
    int64_t period_us;
    int64_t next_utime;

    void add(int leg, const Eigen::Vector3d& position, double heading, const Eigen::Vector3d& velocity) {
        SequenceState q;
        q.index = static_cast<int64_t>(out.size());
        q.utime = next_utime;
        q.leg = leg;
        q.pose.position = position;
        q.pose.yaw = heading;
        q.velocity = velocity;
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
    Builder b{s, {}, std::max<int64_t>(1, std::llround(t.sequence_period * 1e6)), t.start_utime};
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
