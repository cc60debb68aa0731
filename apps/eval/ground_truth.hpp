// Ground truth of a scene in one map's grid: object and seabed voxels
// (voxelise.hpp) and the visible object surface (visibility.hpp). The scene
// part is computed once; each map (its own origin) gets its own grid view.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "grid.hpp"
#include "mesh.hpp"
#include "visibility.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {

struct SceneTruth {
    std::string name;
    std::vector<TriangleMesh> objects, seabed;
    std::vector<SurfaceSample> samples;   // object surface with per-run visibility
    std::vector<std::string> run_names;   // bit k of seen_by = run_names[k]
    int objects_true = 0;                 // separate objects in the object meshes (countObjects)
    Eigen::Vector3d along_track = Eigen::Vector3d::UnitX();
    std::optional<double> declared_face_angle_deg;  // from the scenario, if given
};

struct GroundTruth {
    GridSpec grid;
    MeshVoxels object, seabed;
    VoxelMask visible;                    // object surface voxels seen by any run
    std::vector<VoxelMask> visible_by_run;  // same per run, in run_names order
};

// Object surface voxels holding a sample whose seen_by has any of `run_bits`.
// A sample on a cell boundary counts for every surface cell whose closed box holds it.
[[nodiscard]] VoxelMask markVisibleVoxels(const GridSpec& grid, const VoxelMask& surface,
                                          const std::vector<SurfaceSample>& samples, uint32_t run_bits);

// Loads the meshes and computes the visible object surface (the slow part,
// done once per scenario). Occluders are the objects and the seabed.
[[nodiscard]] SceneTruth makeSceneTruth(const std::string& name, const std::vector<mesh::MeshSource>& object_meshes,
                                        const std::vector<mesh::MeshSource>& seabed_meshes,
                                        const std::vector<SensorRun>& runs, const Eigen::Vector3d& along_track,
                                        const VisibilityOptions& options = {});

[[nodiscard]] GroundTruth groundTruthInGrid(const SceneTruth& scene, const GridSpec& grid);

}  // namespace sonarfusion::eval
