// The project's one triangle mesh and its one reader, shared by the simulator
// (sf_scenario) and the evaluator (sf_eval). OBJ, OFF, PLY and STL (ascii or
// binary) are read with CGAL's polygon-soup readers, Collada with assimp,
// inside mesh_io.cpp, the only translation unit of the library target
// sf_mesh_io; this header is free of both, so no simulator file includes
// them. Polygons are fan-triangulated.
// A scenario may place a file's mesh in its world (scale, then rotate, then
// translate: Placement), so a mesh from another project is used as it is.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sonarfusion::mesh {

struct TriangleMesh {
    std::vector<Eigen::Vector3d> vertices;           // in the file's frame (the scenario's world, NED)
    std::vector<std::array<uint32_t, 3>> triangles;  // indices into vertices, in file order
};

// Where a file's vertices go in the scenario's world:
// world = pose * (scale * file vertex). A uniform positive scale and a
// rotation keep a closed mesh closed and its normals outward.
struct Placement {
    double scale = 1.0;                                   // file units to metres (0.001 for millimetres)
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // rotation, then translation
};

// One mesh of a scene: its file and where it goes.
struct MeshSource {
    std::string path;
    Placement placement;
    MeshSource() = default;
    MeshSource(std::string p, Placement where = {}) : path(std::move(p)), placement(where) {}  // NOLINT: a bare path is a mesh in place
};

// Picks the reader by extension (.obj, .off, .ply, .stl, .dae;
// case-insensitive; STL ascii or binary, its repeated corners merged into
// shared vertices; Collada: every mesh of the file's scene with its node
// transforms, in metres by its <unit>, in the file's own axes).
// Throws std::runtime_error "mesh PATH: ..." when the file cannot be opened or
// read, has an unknown extension, a face with fewer than 3 vertices or an
// index out of range, or no triangles.
[[nodiscard]] TriangleMesh loadMesh(const std::string& path);
// loadMesh(source.path), then placed (a no-op for the default Placement).
[[nodiscard]] TriangleMesh loadMesh(const MeshSource& source);
// Moves every vertex to pose * (scale * v).
void applyPlacement(TriangleMesh& mesh, const Placement& placement);

// Writes a Wavefront OBJ (used by tests).
void saveObj(const TriangleMesh& mesh, const std::string& path);

// Axis-aligned bounds of the vertices (+inf/-inf for an empty mesh).
void meshBounds(const TriangleMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

}  // namespace sonarfusion::mesh

namespace sonarfusion::sim {
using mesh::loadMesh;
using mesh::MeshSource;
using mesh::Placement;
using mesh::saveObj;
using mesh::TriangleMesh;
}  // namespace sonarfusion::sim
