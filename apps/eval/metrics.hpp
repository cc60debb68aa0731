// Reconstruction metrics of docs/design.md ("Evaluation") on voxel sets of one grid
// (docs/evaluation.md says the same in prose).
//
// P = predicted object voxels, G = ground-truth object solid, V = visible
// ground-truth surface. Distances are between voxel centres (exact EDT):
//   correct(p)     : dist(p, G) <= 1 voxel (centre within 0.1 m of the true object)
//   recalled(v)    : dist(v, P) <= 1 voxel
//   precision      = |correct| / |P|
//   recall_visible = |recalled| / |V|
//   iou            = |P & G| / |P | G|
//   chamfer        = mean over P of dist(p, G) (pred->gt), mean over V of
//                    dist(v, P) (gt->pred), and the mean of the two, in cm
//   false_slope    = |P| - |correct| voxels times the voxel volume, m^3
// A value is empty (JSON null) when its denominator set is empty; with no true
// object (G empty) precision, recall, IoU and Chamfer are all null and only
// false_slope (every predicted voxel) is given.
#pragma once

#include <cstddef>
#include <optional>

#include "grid.hpp"

namespace sonarfusion::eval {

// "Within one voxel": squared centre distance <= 1 (face neighbours), with
// slack for rounding. The rule of correct(p) and recalled(v) above, wherever they are counted.
inline constexpr double kWithinOneVoxelSq = 1.0 + 1e-9;

struct VoxelCounts {
    std::size_t predicted = 0;          // |P|
    std::size_t predicted_correct = 0;  // p with dist(p, G) <= 1 voxel
    std::size_t truth = 0;              // |G|
    std::size_t intersection = 0;       // |P & G|
    std::size_t visible_surface = 0;    // |V|
    std::size_t recalled = 0;           // v with dist(v, P) <= 1 voxel
};

struct Metrics {
    VoxelCounts counts;
    std::optional<double> precision, recall_visible, iou;
    std::optional<double> chamfer_cm, chamfer_pred_to_gt_cm, chamfer_gt_to_pred_cm;
    std::optional<double> false_slope_m3;
};

[[nodiscard]] Metrics computeMetrics(const GridSpec& grid, const VoxelMask& predicted, const VoxelMask& truth_solid,
                                     const VoxelMask& visible_surface);

// The voxels of `visible` that P does not recall (no predicted voxel within one voxel).
[[nodiscard]] VoxelMask unrecalled(const GridSpec& grid, const VoxelMask& predicted, const VoxelMask& visible);

// Recall of P on another visible set (e.g. the surface the PS saw), same rule.
[[nodiscard]] std::optional<double> recallOn(const GridSpec& grid, const VoxelMask& predicted, const VoxelMask& visible);

}  // namespace sonarfusion::eval
