// Ground-truth voxelisation of a triangle mesh into the map's grid
// (docs/design.md, "Evaluation").
//
// A cell belongs to the mesh's solid when
//   (a) the mesh is closed and the cell centre is inside or on it
//       (CGAL::Side_of_triangle_mesh), or
//   (b) the surface passes through the cell's interior (CGAL::do_intersect of
//       the triangle with the cell box shrunk by 1e-6 voxel, so a face lying
//       exactly on a cell boundary does not claim the cell on its far side).
// A solid cell is a surface cell when the surface touches its closed box
// (box grown by 1e-6 voxel). An open mesh (e.g. a height-field seabed) has no
// inside: its solid is (b) with the half-open cell [lo, hi), so a sheet lying
// on a cell boundary still claims one cell. Cells outside the grid are dropped.
// A mesh may hold several parts (connected components, e.g. two boxes in one
// file, or the bars of a frame that touch or overlap): the inside is the union
// of the closed parts' insides; `closed` is false when any part is open.
#pragma once

#include <vector>

#include "grid.hpp"
#include "mesh.hpp"

namespace sonarfusion::eval {

struct MeshVoxels {
    VoxelMask solid;    // (a) or (b)
    VoxelMask surface;  // solid cells the surface touches
    bool closed = true; // false when any mesh was open (no inside test for it)
};

[[nodiscard]] MeshVoxels voxeliseMesh(const TriangleMesh& mesh, const GridSpec& grid);
// Union over several meshes (all objects of a scene, or all seabed tiles).
[[nodiscard]] MeshVoxels voxeliseMeshes(const std::vector<TriangleMesh>& meshes, const GridSpec& grid);

// Number of separate objects in these meshes: their connected parts (after
// merging identical vertices; parts meeting only at a vertex or an edge are
// split, see voxelise.cpp), with parts that touch, cross or contain one
// another counted as one object (CGAL Polygon_mesh_processing::do_intersect).
[[nodiscard]] int countObjects(const std::vector<TriangleMesh>& meshes);

}  // namespace sonarfusion::eval
