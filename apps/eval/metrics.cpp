#include "metrics.hpp"

#include <cmath>

#include "distance_transform.hpp"

namespace sonarfusion::eval {

VoxelMask unrecalled(const GridSpec& grid, const VoxelMask& predicted, const VoxelMask& visible) {
    const std::vector<double> to_pred = squaredDistanceToSet(grid, predicted);
    VoxelMask missed(grid.size(), 0);
    for (std::size_t i = 0; i < grid.size(); ++i) missed[i] = visible[i] && to_pred[i] > kWithinOneVoxelSq;
    return missed;
}

std::optional<double> recallOn(const GridSpec& grid, const VoxelMask& predicted, const VoxelMask& visible) {
    const std::size_t n = countSet(visible);
    if (n == 0) return std::nullopt;
    return static_cast<double>(n - countSet(unrecalled(grid, predicted, visible))) / static_cast<double>(n);
}

Metrics computeMetrics(const GridSpec& grid, const VoxelMask& predicted, const VoxelMask& truth_solid,
                       const VoxelMask& visible_surface) {
    const std::vector<double> to_truth = squaredDistanceToSet(grid, truth_solid);
    const std::vector<double> to_pred = squaredDistanceToSet(grid, predicted);
    Metrics m;
    VoxelCounts& c = m.counts;
    double sum_pred_to_gt = 0.0, sum_gt_to_pred = 0.0;
    std::size_t union_count = 0;
    for (std::size_t i = 0; i < grid.size(); ++i) {
        const bool p = predicted[i] != 0, g = truth_solid[i] != 0;
        c.truth += g;
        c.intersection += p && g;
        union_count += p || g;
        if (p) {
            ++c.predicted;
            c.predicted_correct += to_truth[i] <= kWithinOneVoxelSq;
            sum_pred_to_gt += std::sqrt(to_truth[i]);
        }
        if (visible_surface[i]) {
            ++c.visible_surface;
            c.recalled += to_pred[i] <= kWithinOneVoxelSq;
            sum_gt_to_pred += std::sqrt(to_pred[i]);
        }
    }
    const double voxel_cm = grid.resolution * 100.0;
    // Without a true object (bare seabed) every predicted voxel is false: only
    // the false volume is defined, precision, IoU and Chamfer are null.
    if (c.predicted > 0 && c.truth > 0) {
        m.precision = static_cast<double>(c.predicted_correct) / static_cast<double>(c.predicted);
        m.chamfer_pred_to_gt_cm = sum_pred_to_gt / static_cast<double>(c.predicted) * voxel_cm;
    }
    if (c.predicted > 0)
        m.false_slope_m3 = static_cast<double>(c.predicted - c.predicted_correct) * std::pow(grid.resolution, 3);
    if (c.visible_surface > 0) {
        m.recall_visible = static_cast<double>(c.recalled) / static_cast<double>(c.visible_surface);
        if (c.predicted > 0) m.chamfer_gt_to_pred_cm = sum_gt_to_pred / static_cast<double>(c.visible_surface) * voxel_cm;
    }
    if (m.chamfer_pred_to_gt_cm && m.chamfer_gt_to_pred_cm)
        m.chamfer_cm = 0.5 * (*m.chamfer_pred_to_gt_cm + *m.chamfer_gt_to_pred_cm);
    if (c.truth > 0 && union_count > 0) m.iou = static_cast<double>(c.intersection) / static_cast<double>(union_count);
    return m;
}

}  // namespace sonarfusion::eval
