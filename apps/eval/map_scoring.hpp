// Scores one saved map against the ground truth: segments it with the config
// of its variant (applyVariant + Segmenter, as the mapper does) and computes
// the metrics and end-face angles.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "end_face.hpp"
#include "ground_truth.hpp"
#include "metrics.hpp"
#include "sonarfusion/config.hpp"
#include "sonarfusion/segmentation.hpp"
#include "sonarfusion/variant.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion::eval {

struct Prediction {
    VoxelMask object;    // voxels with an object label
    VoxelMask occupied;  // p above the segmentation threshold
    SegmentationStats stats;
};

// Segments as sf-mapper does: `base` (MapperConfig defaults, or the mapper's
// YAML via sf-eval --config) with the preset of `variant` applied, the seabed
// averaged along `along_track` (unit north, east; zero: square window).
[[nodiscard]] Prediction segmentMap(const VoxelMap& map, Variant variant, const MapperConfig& base,
                                    const Eigen::Vector2d& along_track);
// MapperConfig defaults, no track axis.
[[nodiscard]] Prediction segmentMap(const VoxelMap& map, Variant variant);

// Why the visible surface voxels that no predicted voxel recalls (metrics.hpp:
// none within one voxel) were missed, by the map's own state at each: the map
// says water there (log-odds < 0, with or without PS echoes in the voxel), it
// was barely or never observed (0 to the occupied threshold), or it is occupied
// but in no object: a PS ray reached it (not echo-confirmed, or confirmed but
// not connected) or none did (outside the PS swath). docs/evaluation.md.
struct MissedVisible {
    std::size_t free_with_ps_echoes = 0;
    std::size_t free = 0;
    std::size_t not_occupied = 0;
    std::size_t occupied_ps_observed = 0;
    std::size_t occupied_outside_ps = 0;
    [[nodiscard]] std::size_t total() const {
        return free_with_ps_echoes + free + not_occupied + occupied_ps_observed + occupied_outside_ps;
    }
};
[[nodiscard]] MissedVisible missedVisible(const GridSpec& grid, const VoxelMap& map, const Prediction& prediction,
                                          const VoxelMask& visible);

struct VariantScore {
    std::string variant;
    std::string map_path;
    Metrics metrics;
    std::vector<std::pair<std::string, std::optional<double>>> recall_by_run;  // ("ps", 0.97), ...
    std::vector<FaceAngle> faces;          // front (+along-track) first
    std::optional<double> face_angle_deg;  // mean of the faces that have an angle
    std::optional<double> true_face_angle_deg;
    SegmentationStats segmentation;
    int objects = 0;       // predicted (segmentation)
    int objects_true = 0;  // in the scene's object meshes (SceneTruth::objects_true)
    std::optional<MissedVisible> missed;  // with the map at hand (sf-eval --map)
};

[[nodiscard]] VariantScore scorePrediction(const GridSpec& grid, const Prediction& prediction, const GroundTruth& gt,
                                           const SceneTruth& scene, const EndFaceSelection& selection = {});

}  // namespace sonarfusion::eval
