// A plain triangle mesh (no CGAL types) that the evaluator's modules pass
// around; CGAL structures are built from it inside the .cpp files only.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace sonarfusion::eval {

struct TriangleMesh {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::array<int, 3>> triangles;
};

// OFF, OBJ or PLY (ascii or binary, by extension) through CGAL's polygon-soup
// reader; polygons are fan-triangulated. Throws std::runtime_error naming the
// file on failure or on an empty mesh.
[[nodiscard]] TriangleMesh loadMesh(const std::string& path);

// Axis-aligned bounds of the vertices.
void meshBounds(const TriangleMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

}  // namespace sonarfusion::eval
