// Survey scoring (issue 13, docs/evaluation.md "Survey scoring"): the
// published objects of every finalised map of a survey (sf-mapper --map-dir)
// against every true object of the scenario (each `role: object` mesh).
//
// Matching rule, per predicted object o of map m:
//   overlap(o, t) = voxels of o within one voxel (centre distance <= 1 voxel)
//                   of true object t's solid in m's grid;
//   o matches the t with the largest overlap (ties: lower true index);
//   overlap 0 with every t: o is a false detection.
// Per true object, of the predicted objects matching it the one with the
// largest overlap is THE match (ties: lower map id, then lower object id);
// the others are duplicates, counted as false. A true object is found when it
// has a match. Per match: precision, visible recall and Chamfer (metrics.hpp)
// of the object's voxels against that true object alone, in the map's grid.
//
// No CGAL here: voxelise.hpp and visibility.hpp keep it in their .cpp files.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "grid.hpp"
#include "mesh.hpp"
#include "metrics.hpp"
#include "nav_error.hpp"
#include "sonarfusion/config.hpp"
#include "visibility.hpp"

namespace sonarfusion::eval {

// One object as the mapper published it (map_<k>.objects.json), or as sf-eval
// segmented it from the map when the map has no objects file.
struct PredictedObject {
    int id = 0;
    std::vector<std::size_t> voxels;  // linear indices (z*ny+y)*nx+x into its map's grid
    int voxel_count = 0;
    double volume_m3 = 0.0, height_m = 0.0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), bbox_min = Eigen::Vector3d::Zero(),
                    bbox_max = Eigen::Vector3d::Zero();
    bool ps_confirmed = false;
};

// A true object's voxels in one map's grid (only for objects whose bounds
// reach into the grid).
struct TrueInGrid {
    int true_index = -1;
    VoxelMask solid;                        // G_t
    VoxelMask visible;                      // V_t: its surface voxels seen by any run
    std::vector<VoxelMask> visible_by_run;  // per run, in run_names order
    bool clipped = false;                   // part of the object lies outside the grid
};

struct SurveyMap {
    int map_id = 0;
    std::string map_path, objects_path;
    std::string variant;          // from the map file's header
    std::string objects_source;   // "published" (objects.json) or "segmented" (no objects file)
    GridSpec grid;
    std::vector<PredictedObject> objects;
    std::vector<TrueInGrid> truths;  // filled by truthInMaps()
};

// The scene's true objects with their visible surface samples. Visibility is
// computed per object, from the poses within range of it, against the
// occluders (objects, seabed) within range of it: the same answer as the
// whole-scene rule, found without testing a 60 m survey's every pose.
struct SurveyTrueObject {
    std::string name;  // mesh file stem
    TriangleMesh mesh;
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  // vertex bounds
    std::vector<SurfaceSample> samples;
};

struct SurveyTruth {
    std::vector<SurveyTrueObject> objects;
    std::vector<std::string> run_names;
};

[[nodiscard]] SurveyTruth makeSurveyTruth(const std::vector<mesh::MeshSource>& object_meshes,
                                          const std::vector<mesh::MeshSource>& seabed_meshes,
                                          const std::vector<SensorRun>& runs, const VisibilityOptions& options = {});
// The same from meshes already loaded (tests).
[[nodiscard]] SurveyTruth makeSurveyTruth(std::vector<SurveyTrueObject> objects, const std::vector<TriangleMesh>& seabed,
                                          const std::vector<SensorRun>& runs, const VisibilityOptions& options = {});

// Voxelises every true object whose bounds reach into a map's grid, there.
void truthInMaps(const SurveyTruth& truth, std::vector<SurveyMap>& maps);

// Reads DIR/map_<k>.map (header: the grid) and DIR/map_<k>.objects.json for
// every k, in id order. Checks the objects file against the map (map id,
// origin, resolution, dims, voxel indices) and throws std::runtime_error
// naming the file on any mismatch. A map without an objects file is kept with
// objects_source "segmented" and no objects (segmentSurveyMap fills them).
[[nodiscard]] std::vector<SurveyMap> readSurveyDir(const std::string& dir);
// Parses one objects file into `map` (its grid must be set).
void readObjectsJson(const std::string& path, SurveyMap& map);
// Objects of a map segmented as sf-mapper does (map_scoring.hpp's segmentMap
// with the map's variant), for a map that has no objects file.
void segmentSurveyMap(SurveyMap& map, const MapperConfig& base, const Eigen::Vector2d& along_track);

enum class MatchRole { Match, Duplicate, False };

struct Assignment {
    int map_index = 0, object_index = 0;  // into maps, maps[map_index].objects
    int true_index = -1;                  // -1: matches nothing
    std::size_t overlap = 0;              // voxels within one voxel of that true object
    MatchRole role = MatchRole::False;
};

// The matching rule above; one Assignment per predicted object, in map order.
[[nodiscard]] std::vector<Assignment> matchSurvey(const std::vector<SurveyMap>& maps, int true_objects);

struct ObjectScore {
    int true_index = 0;
    std::string name;
    Eigen::Vector3d true_centroid = Eigen::Vector3d::Zero();  // of the mesh's bounds
    bool found = false;
    int map_id = 0, object_id = 0;
    std::size_t overlap = 0;
    int duplicates = 0;
    bool clipped = false;
    Metrics metrics;
    std::vector<std::pair<std::string, std::optional<double>>> recall_by_run;
    Eigen::Vector3d predicted_centroid = Eigen::Vector3d::Zero();
    double centroid_error_m = 0.0;  // horizontal distance of the two centroids
};

struct SurveyScore {
    int truth = 0, found = 0, false_detections = 0, duplicates = 0, predicted = 0;
    std::vector<ObjectScore> objects;       // one per true object, in scenario order
    std::vector<Assignment> assignments;    // one per predicted object
};

[[nodiscard]] SurveyScore scoreSurvey(const SurveyTruth& truth, const std::vector<SurveyMap>& maps);

// report.json of a survey (docs/evaluation.md): "mode": "survey", "detection",
// "objects" (per true object), "predicted" (per published object), "maps",
// and "navigation" when asked. Written atomically.
[[nodiscard]] std::string surveyReportJson(const std::string& scenario, const SurveyScore& score,
                                           const std::vector<SurveyMap>& maps, const NavigationReport& navigation = {});
void writeSurveyReport(const std::string& path, const std::string& scenario, const SurveyScore& score,
                       const std::vector<SurveyMap>& maps, const NavigationReport& navigation = {});
// sf-eval --figures in survey mode: per map, DIR/survey_map_<k>_objects.ply (the published objects'
// voxel centres, coloured by role: green match, orange duplicate, red false) and
// DIR/survey_map_<k>_truth.ply (the true objects' solid voxels in that grid: grey, the visible
// surface blue). ASCII PLY, world NED. Returns the paths.
std::vector<std::string> writeSurveyPointClouds(const std::string& dir, const std::vector<SurveyMap>& maps,
                                                const SurveyScore& score);
// sf-eval --figures in survey mode, per map: DIR/map_<k>/eval_<variant>_{side,top}[_objects].png,
// the projections of figures.hpp (occupied voxels with p above `occupied_probability`, and the
// published objects' voxels), windowed on the true objects in that map's grid (the whole map when
// none), their outlines red, the seabed cropped to the map grey. Returns the paths.
std::vector<std::string> writeSurveyFigures(const std::string& dir, const std::string& scenario,
                                            const SurveyTruth& truth, const std::vector<mesh::MeshSource>& seabed_meshes,
                                            const std::vector<SurveyMap>& maps, double occupied_probability);
// The per-object table printed on stdout.
[[nodiscard]] std::string surveyTable(const SurveyScore& score);

}  // namespace sonarfusion::eval
