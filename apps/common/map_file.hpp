// The mapper's map file: a small documented binary format (docs/map-format.md)
// plus a PLY point cloud of the occupied voxels for MeshLab/CloudCompare.
// Writes are atomic: a temporary file renamed over the target.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sonarfusion/variant.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct MapFileHeader {
    int nx = 0, ny = 0, nz = 0;
    double resolution = 0.0;
    double origin[3] = {0, 0, 0};
    float clamp_min = -5.0f, clamp_max = 5.0f;
    bool initialised = false;
    std::string variant;  // fls_only, carve_only, paper, fused
    int version = 3;      // 1: no above-seabed FLS vote counts, 2: no PS crossing counts (docs/map-format.md)
};

// Throws std::runtime_error with the path and the reason on any failure.
void saveMap(const std::string& path, const VoxelMap& map, const std::string& variant);
// Reads the header only.
[[nodiscard]] MapFileHeader readMapHeader(const std::string& path);
// Loads into `map`, whose dimensions must match the file's.
MapFileHeader loadMap(const std::string& path, VoxelMap& map);
// MapConfig with the file's grid, for constructing a VoxelMap to load into.
[[nodiscard]] MapConfig mapConfigOf(const MapFileHeader& h);

// ASCII PLY of voxel centres with p > probability_threshold; `only_labelled`
// (optional, per voxel, non-zero to keep) restricts it further.
void savePly(const std::string& path, const VoxelMap& map, double probability_threshold,
             const std::vector<int32_t>* only_labelled = nullptr);

}  // namespace sonarfusion
