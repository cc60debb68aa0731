// Minimal triangle-mesh readers for OBJ, OFF and PLY (ascii or binary little
// endian). Polygons are fan-triangulated. Throws std::runtime_error naming the
// file and line/element on malformed input.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sonarfusion::sim {

struct TriangleMesh {
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
};

// Picks the reader by extension (.obj, .off, .ply; case-insensitive).
[[nodiscard]] TriangleMesh loadMesh(const std::string& path);

// Writes a Wavefront OBJ (used by tests and the scene generator's C++ callers).
void saveObj(const TriangleMesh& mesh, const std::string& path);

}  // namespace sonarfusion::sim
