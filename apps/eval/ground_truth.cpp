#include "ground_truth.hpp"

#include <cmath>

namespace sonarfusion::eval {

VoxelMask markVisibleVoxels(const GridSpec& grid, const VoxelMask& surface, const std::vector<SurfaceSample>& samples,
                            uint32_t run_bits) {
    constexpr double kBoundary = 1e-6;  // voxels
    VoxelMask out(grid.size(), 0);
    for (const SurfaceSample& s : samples) {
        if (!(s.seen_by & run_bits)) continue;
        const Eigen::Vector3d c = grid.toCell(s.point);
        int lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = static_cast<int>(std::floor(c[k] - kBoundary));
            hi[k] = static_cast<int>(std::floor(c[k] + kBoundary));
        }
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    if (!grid.contains(x, y, z)) continue;
                    const std::size_t i = grid.linear(x, y, z);
                    if (surface[i]) out[i] = 1;
                }
    }
    return out;
}

SceneTruth makeSceneTruth(const std::string& name, const std::vector<mesh::MeshSource>& object_meshes,
                          const std::vector<mesh::MeshSource>& seabed_meshes, const std::vector<SensorRun>& runs,
                          const Eigen::Vector3d& along_track, const VisibilityOptions& options) {
    SceneTruth scene;
    scene.name = name;
    scene.along_track = along_track;
    for (const auto& p : object_meshes) scene.objects.push_back(loadMesh(p));
    for (const auto& p : seabed_meshes) scene.seabed.push_back(loadMesh(p));
    std::vector<TriangleMesh> occluders = scene.objects;
    occluders.insert(occluders.end(), scene.seabed.begin(), scene.seabed.end());
    scene.samples = sampleVisibleSurface(scene.objects, occluders, runs, options);
    for (const auto& r : runs) scene.run_names.push_back(r.name);
    scene.objects_true = countObjects(scene.objects);
    return scene;
}

GroundTruth groundTruthInGrid(const SceneTruth& scene, const GridSpec& grid) {
    GroundTruth gt;
    gt.grid = grid;
    gt.object = voxeliseMeshes(scene.objects, grid);
    gt.seabed = voxeliseMeshes(scene.seabed, grid);
    gt.visible = markVisibleVoxels(grid, gt.object.surface, scene.samples, ~0u);
    for (std::size_t k = 0; k < scene.run_names.size() && k < 32; ++k)
        gt.visible_by_run.push_back(markVisibleVoxels(grid, gt.object.surface, scene.samples, 1u << k));
    return gt;
}

}  // namespace sonarfusion::eval
