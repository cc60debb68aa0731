#include "sonarfusion/voxel_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sonarfusion {

VoxelMap::VoxelMap(const MapConfig& cfg)
    : nx_(cfg.nx), ny_(cfg.ny), nz_(cfg.nz), resolution_(cfg.resolution),
      clamp_min_(cfg.clamp_min), clamp_max_(cfg.clamp_max), snap_to_lattice_(cfg.snap_to_world_lattice) {
    if (nx_ <= 0 || ny_ <= 0 || nz_ <= 0 || nx_ > 4096 || ny_ > 4096 || nz_ > 4096)
        throw std::invalid_argument("map dimensions must be in 1..4096");
    if (!(resolution_ > 0.0) || !std::isfinite(resolution_))
        throw std::invalid_argument("map resolution must be a positive number");
    if (!(clamp_min_ < 0.0f && clamp_max_ > 0.0f))
        throw std::invalid_argument("map clamp must satisfy clamp_min < 0 < clamp_max");
    const std::size_t n = static_cast<std::size_t>(nx_) * ny_ * nz_;
    log_odds_.assign(n, 0.0f);
    flags_.assign(n, 0);
}

void VoxelMap::clear() {
    std::fill(log_odds_.begin(), log_odds_.end(), 0.0f);
    std::fill(flags_.begin(), flags_.end(), uint8_t{0});
}

void VoxelMap::initialiseAt(const Eigen::Vector3d& centre) {
    clear();
    origin_ = centre - 0.5 * extent();
    if (snap_to_lattice_) origin_ = (origin_ / resolution_).array().round().matrix() * resolution_;
    initialised_ = true;
}

Eigen::Vector3d VoxelMap::centre() const { return origin_ + 0.5 * extent(); }

bool VoxelMap::worldToIndex(const Eigen::Vector3d& p, VoxelIndex& out) const {
    const Eigen::Vector3d f = (p - origin_) / resolution_;
    if (!f.allFinite()) return false;
    // floor() before the int cast: truncation would fold (-1, 0) into voxel 0.
    const double fx = std::floor(f.x()), fy = std::floor(f.y()), fz = std::floor(f.z());
    if (fx < 0.0 || fy < 0.0 || fz < 0.0 || fx >= nx_ || fy >= ny_ || fz >= nz_) return false;
    out = VoxelIndex{static_cast<int>(fx), static_cast<int>(fy), static_cast<int>(fz)};
    return true;
}

Eigen::Vector3d VoxelMap::centreOf(const VoxelIndex& v) const {
    return origin_ + (Eigen::Vector3d(v.x, v.y, v.z) + Eigen::Vector3d::Constant(0.5)) * resolution_;
}

VoxelIndex VoxelMap::fromLinear(std::size_t i) const {
    VoxelIndex v;
    v.x = static_cast<int>(i % nx_);
    i /= nx_;
    v.y = static_cast<int>(i % ny_);
    v.z = static_cast<int>(i / ny_);
    return v;
}

}  // namespace sonarfusion
