#include "scenario_source.hpp"

#include <cmath>

#include "scenario.hpp"
#include "sonarfusion/pose.hpp"
#include "sonarfusion/track_axis.hpp"
#include "trajectory.hpp"

namespace sonarfusion::eval {

EvalScenario loadEvalScenario(const std::string& path) {
    const sim::Scenario s = sim::loadScenario(path);
    EvalScenario out;
    out.name = s.name;
    out.object_meshes = s.meshPaths(sim::MeshRole::Object);
    out.seabed_meshes = s.meshPaths(sim::MeshRole::Seabed);
    if (s.trueFaceAngleDeg() > 0.0) out.declared_face_angle_deg = s.trueFaceAngleDeg();
    if (!s.trajectory.passes.empty()) {
        const double h = s.trajectory.passes.front().heading;
        out.along_track = Eigen::Vector3d(std::cos(h), std::sin(h), 0.0);
    }
    SensorRun fls{"fls", SensorFov::fls(s.fls), {}};
    SensorRun ps{"ps", SensorFov::ps(s.ps), {}};
    TrackAxis track;
    for (const sim::SequenceState& q : sim::buildSequences(s)) {
        track.add(q.pose.yaw);
        const Eigen::Isometry3d ps_pose = sensorToWorld(q.pose, s.ps_mount);
        ps.poses.push_back({ps_pose.translation(), ps_pose.linear()});
        if (q.has_fls) {
            const Eigen::Isometry3d fls_pose = sensorToWorld(q.pose, s.fls_mount);
            fls.poses.push_back({fls_pose.translation(), fls_pose.linear()});
        }
    }
    out.track_axis = track.axis();
    out.runs = {fls, ps};
    return out;
}

}  // namespace sonarfusion::eval
