#include "map_scoring.hpp"

#include "sonarfusion/config.hpp"

namespace sonarfusion::eval {

Prediction segmentMap(const VoxelMap& map, Variant variant) {
    return segmentMap(map, variant, MapperConfig{}, Eigen::Vector2d::Zero());
}

Prediction segmentMap(const VoxelMap& map, Variant variant, const MapperConfig& base,
                      const Eigen::Vector2d& along_track) {
    MapperConfig cfg = base;
    applyVariant(variant, cfg);  // as sf-mapper --variant does
    Segmenter seg(cfg.segmentation, cfg.update.require_ps_observation, map);
    seg.setAlongTrack(along_track);
    Prediction p;
    p.stats = seg.run(map);
    p.object.assign(map.size(), 0);
    p.occupied.assign(map.size(), 0);
    for (std::size_t i = 0; i < map.size(); ++i) {
        p.object[i] = seg.objectLabel(i) > 0;
        p.occupied[i] = seg.occupied(i);
    }
    return p;
}

MissedVisible missedVisible(const GridSpec& grid, const VoxelMap& map, const Prediction& prediction,
                            const VoxelMask& visible) {
    MissedVisible m;
    const VoxelMask missed = unrecalled(grid, prediction.object, visible);
    for (std::size_t i = 0; i < grid.size(); ++i) {
        if (!missed[i]) continue;
        const float l = map.logOdds(i);
        if (l < 0.0f) ++(map.psEchoCount(i) > 0 ? m.free_with_ps_echoes : m.free);
        else if (!prediction.occupied[i]) ++m.not_occupied;
        else ++(map.psObserved(i) ? m.occupied_ps_observed : m.occupied_outside_ps);
    }
    return m;
}

VariantScore scorePrediction(const GridSpec& grid, const Prediction& prediction, const GroundTruth& gt,
                             const SceneTruth& scene, const EndFaceSelection& selection) {
    VariantScore s;
    s.metrics = computeMetrics(grid, prediction.object, gt.object.solid, gt.visible);
    for (std::size_t k = 0; k < gt.visible_by_run.size(); ++k)
        s.recall_by_run.emplace_back(scene.run_names[k], recallOn(grid, prediction.object, gt.visible_by_run[k]));
    double sum = 0.0, truth_sum = 0.0;
    int n = 0, n_truth = 0;
    for (const TriangleMesh& object : scene.objects)
        for (const EndFace& face : findEndFaces(object, scene.along_track)) {
            s.faces.push_back(measureEndFace(grid, prediction.object, face, selection));
            truth_sum += face.true_angle_deg;
            ++n_truth;
            if (s.faces.back().angle_deg) {
                sum += *s.faces.back().angle_deg;
                ++n;
            }
        }
    if (n > 0) s.face_angle_deg = sum / n;
    if (scene.declared_face_angle_deg) s.true_face_angle_deg = scene.declared_face_angle_deg;
    else if (n_truth > 0) s.true_face_angle_deg = truth_sum / n_truth;
    s.segmentation = prediction.stats;
    s.objects = prediction.stats.objects;
    s.objects_true = scene.objects_true;
    return s;
}

}  // namespace sonarfusion::eval
