// Figures in the manner of the paper's Figs. 8-9: side (along-track x vs
// depth) and top (x vs y) projections of each map's occupied voxels, coloured
// by how many occupied voxels lie along the projection axis, with the true
// object outline (mesh silhouette) in red and the seabed in grey; plus PLY
// point clouds. OpenCV stays in figures.cpp.
#pragma once

#include <string>
#include <vector>

#include "ground_truth.hpp"
#include "map_scoring.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion::eval {

struct FigurePanel {
    std::string variant;
    const VoxelMap* map = nullptr;
    const Prediction* prediction = nullptr;
    const GroundTruth* truth = nullptr;
};

// DIR/eval_<variant>_side.png, eval_<variant>_top.png and, with more than one
// panel, eval_side_all.png / eval_top_all.png stacking them; the same with
// suffix _objects (eval_<variant>_side_objects.png, eval_side_objects_all.png,
// ...) counting only the object voxels that are scored. Returns the paths.
std::vector<std::string> writeFigures(const std::string& dir, const std::string& scenario, const SceneTruth& scene,
                                      const std::vector<FigurePanel>& panels);

// DIR/<variant>_occupied.ply, <variant>_objects.ply and gt_object.ply,
// gt_visible.ply in the panel's grid. Returns the paths.
std::vector<std::string> writePointClouds(const std::string& dir, const FigurePanel& panel, bool with_truth);

}  // namespace sonarfusion::eval
