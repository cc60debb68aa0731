// The project's one triangle mesh and its one reader, shared by the simulator
// (sf_scenario) and the evaluator (sf_eval). OBJ, OFF and PLY (ascii or
// binary) are read with CGAL's polygon-soup readers inside mesh_io.cpp, the
// only translation unit of the library target sf_mesh_io; this header is free
// of CGAL, so no simulator file includes it. Polygons are fan-triangulated.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sonarfusion::mesh {

struct TriangleMesh {
    std::vector<Eigen::Vector3d> vertices;           // in the file's frame (the scenario's world, NED)
    std::vector<std::array<uint32_t, 3>> triangles;  // indices into vertices, in file order
};

// Picks the reader by extension (.obj, .off, .ply; case-insensitive). Throws
// std::runtime_error "mesh PATH: ..." when the file cannot be opened or read,
// has an unknown extension, a face with fewer than 3 vertices or an index out
// of range, or no triangles.
[[nodiscard]] TriangleMesh loadMesh(const std::string& path);

// Writes a Wavefront OBJ (used by tests).
void saveObj(const TriangleMesh& mesh, const std::string& path);

// Axis-aligned bounds of the vertices (+inf/-inf for an empty mesh).
void meshBounds(const TriangleMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

}  // namespace sonarfusion::mesh

namespace sonarfusion::sim {
using mesh::loadMesh;
using mesh::saveObj;
using mesh::TriangleMesh;
}  // namespace sonarfusion::sim
