#include "scenario_source.hpp"

#include <algorithm>
#include <cmath>

#include "scenario.hpp"
#include "sonarfusion/pose.hpp"
#include "sonarfusion/track_axis.hpp"
#include "navigation.hpp"
#include "trajectory.hpp"

namespace sonarfusion::eval {

EvalScenario loadEvalScenario(const std::string& path) {
    const sim::Scenario s = sim::loadScenario(path);
    EvalScenario out;
    out.name = s.name;
    for (const sim::MeshSpec& m : s.scene.meshes)
        (m.role == sim::MeshRole::Object ? out.object_meshes : out.seabed_meshes)
            .push_back(mesh::MeshSource{m.path, {m.scale, m.pose()}});
    if (s.trueFaceAngleDeg() > 0.0) out.declared_face_angle_deg = s.trueFaceAngleDeg();
    if (!s.trajectory.passes.empty()) {
        const double h = s.trajectory.passes.front().heading;
        out.along_track = Eigen::Vector3d(std::cos(h), std::sin(h), 0.0);
    }
    SensorRun fls{"fls", SensorFov::fls(s.fls), {}};
    SensorRun ps{"ps", SensorFov::ps(s.ps), {}};
    out.nav_channel = s.channels.nav;
    out.truth_channel = s.channels.nav_truth;
    // An FLS frame is the largest message: its pixels plus per-beam and per-row floats.
    const std::size_t fls_bytes = static_cast<std::size_t>(s.fls.beams) * static_cast<std::size_t>(s.fls.rows) +
                                  4 * static_cast<std::size_t>(s.fls.beams + s.fls.rows) + 4096;
    out.max_message_bytes = std::max<std::size_t>(out.max_message_bytes, fls_bytes);
    TrackAxis track;
    const std::vector<sim::SequenceState> sequences = sim::buildSequences(s);
    // The mapper's track axis comes from the NAV headings; the visibility
    // poses below are the true ones (the world frame is the truth's).
    for (const sim::NavReport& r : sim::reportNavigation(s, sequences)) track.add(r.reported.yaw);
    for (const sim::SequenceState& q : sequences) {
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
