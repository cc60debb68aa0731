// The final map as an OctoMap (octomap::OcTree binary, .bt) that octovis,
// octomap-tools and ROS's octomap_server open (docs/map-format.md, "OctoMap").
// One conversion for `sf-mapper --octomap-out` and `sf-map2octomap`.
//
// Frame: ROS's map frame, ENU (x east, y north, z up; REP-103), the frame
// tools/sf-bag writes NAV in, so the tree lines up with a bag's poses in RViz:
// a voxel centre at NED (n, e, d) is written at (e, n, -d). Resolution: the
// map's. Voxels: every voxel with log-odds != 0 (touched by an update) is a
// known leaf; occupied exactly when its log-odds exceeds
// float(logit(occupied_probability)) (the set the map snapshot and the
// segmentation use), free otherwise; voxels never updated stay unknown. The
// .bt format keeps the occupied/free state only (not the log-odds).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>

#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct OctomapExportStats {
    std::size_t occupied = 0;  // leaves written occupied
    std::size_t free = 0;      // leaves written free
};

// Whether voxel i is in the occupied set written to the tree.
[[nodiscard]] bool octomapOccupied(const VoxelMap& map, std::size_t i, double occupied_probability);
// World ENU position of voxel i's centre (where the tree holds it).
[[nodiscard]] Eigen::Vector3d enuCentreOf(const VoxelMap& map, std::size_t i);

// Writes `path` atomically (path.tmp, renamed). Throws std::runtime_error with
// the path and reason on failure, or when a voxel falls outside OctoMap's key
// range (+-32768 voxels around the world origin).
OctomapExportStats writeOctomap(const std::string& path, const VoxelMap& map, double occupied_probability);

}  // namespace sonarfusion
