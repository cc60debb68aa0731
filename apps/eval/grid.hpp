// The evaluation grid: the map's voxel lattice (origin = min corner, linear
// index (iz*ny+iy)*nx+ix, NED) and per-voxel masks on it. Kept apart from
// VoxelMap so ground truth and metrics need no log-odds storage.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion::eval {

using VoxelMask = std::vector<uint8_t>;  // one byte per voxel, non-zero = set

struct GridSpec {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // min corner, NED
    double resolution = 0.1;
    int nx = 0, ny = 0, nz = 0;

    [[nodiscard]] static GridSpec of(const VoxelMap& map) {
        return {map.origin(), map.resolution(), map.nx(), map.ny(), map.nz()};
    }
    [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(nx) * ny * nz; }
    [[nodiscard]] bool contains(int x, int y, int z) const {
        return x >= 0 && y >= 0 && z >= 0 && x < nx && y < ny && z < nz;
    }
    [[nodiscard]] std::size_t linear(int x, int y, int z) const {
        return latticeIndex(static_cast<std::size_t>(x), static_cast<std::size_t>(y), static_cast<std::size_t>(z),
                            static_cast<std::size_t>(nx), static_cast<std::size_t>(ny));
    }
    [[nodiscard]] Eigen::Vector3i index(std::size_t i) const {
        const std::size_t layer = static_cast<std::size_t>(nx) * ny;
        return {static_cast<int>(i % nx), static_cast<int>((i % layer) / nx), static_cast<int>(i / layer)};
    }
    [[nodiscard]] Eigen::Vector3d centre(int x, int y, int z) const {
        return origin + (Eigen::Vector3d(x, y, z).array() + 0.5).matrix() * resolution;
    }
    [[nodiscard]] Eigen::Vector3d centre(std::size_t i) const {
        const Eigen::Vector3i v = index(i);
        return centre(v.x(), v.y(), v.z());
    }
    // Continuous voxel coordinate of a world point (cell k spans [k, k+1)).
    [[nodiscard]] Eigen::Vector3d toCell(const Eigen::Vector3d& p) const { return (p - origin) / resolution; }
    [[nodiscard]] bool operator==(const GridSpec& o) const {
        return origin == o.origin && resolution == o.resolution && nx == o.nx && ny == o.ny && nz == o.nz;
    }
};

[[nodiscard]] inline std::size_t countSet(const VoxelMask& m) {
    std::size_t n = 0;
    for (uint8_t v : m) n += v != 0;
    return n;
}

}  // namespace sonarfusion::eval
