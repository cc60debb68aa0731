// The only part of sf-eval that knows the scenario format (read by the shared
// config reader, config/scenario.hpp): turns a scenario file into the
// evaluator's plain inputs (mesh paths, sensor poses and fields of view,
// along-track axis).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mesh.hpp"
#include "visibility.hpp"

namespace sonarfusion::eval {

struct EvalScenario {
    std::string name;
    std::vector<mesh::MeshSource> object_meshes, seabed_meshes;  // files and where the scenario places them
    std::vector<SensorRun> runs;  // "fls" (frames only), "ps" (every sequence), from the TRUE poses
    Eigen::Vector3d along_track = Eigen::Vector3d::UnitX();  // heading of the first pass
    // Axial mean of the vehicle headings of every sequence (one NAV each), as
    // the mapper's TrackAxis sees them (the NAV's headings, heading errors
    // included); zero when they do not share one axis.
    Eigen::Vector2d track_axis = Eigen::Vector2d::Zero();
    std::string nav_channel = "NAV", truth_channel = "NAV_TRUTH";  // the scenario's channel names
    std::size_t max_message_bytes = 1 << 20;  // bounds one LCM event of this scenario's messages
    std::optional<double> declared_face_angle_deg;
};

// Throws on bad input: sim::ScenarioError naming the field (the scenario is read
// by the shared config reader, sf_config_yaml's loadScenario), std::runtime_error.
[[nodiscard]] EvalScenario loadEvalScenario(const std::string& path);

}  // namespace sonarfusion::eval
