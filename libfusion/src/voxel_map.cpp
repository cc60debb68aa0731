#include "sonarfusion/voxel_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sonarfusion {

VoxelMap::VoxelMap(const MapConfig& cfg)
    : nx_(cfg.nx), ny_(cfg.ny), nz_(cfg.nz), resolution_(cfg.resolution),
      clamp_min_(cfg.clamp_min), clamp_max_(cfg.clamp_max), snap_to_lattice_(cfg.snap_to_world_lattice) {
    if (nx_ <= 0 || ny_ <= 0 || nz_ <= 0 || nx_ > kMaxMapCells || ny_ > kMaxMapCells || nz_ > kMaxMapCells)
        throw std::invalid_argument("map dimensions must be in 1.." + std::to_string(kMaxMapCells));
    if (!(resolution_ > 0.0) || !std::isfinite(resolution_))
        throw std::invalid_argument("map resolution must be a positive number");
    if (!(clamp_min_ < 0.0f && clamp_max_ > 0.0f))
        throw std::invalid_argument("map clamp must satisfy clamp_min < 0 < clamp_max");
    const std::size_t n = static_cast<std::size_t>(nx_) * ny_ * nz_;
    log_odds_.assign(n, 0.0f);
    ps_observed_.assign(n, 0);
    fls_touched_.assign(n, 0);
    ps_echoes_.assign(n, 0);
    above_seabed_votes_.assign(n, 0);
    ps_crossings_.assign(n, 0);
}

void VoxelMap::clear() {
    std::fill(log_odds_.begin(), log_odds_.end(), 0.0f);
    std::fill(ps_observed_.begin(), ps_observed_.end(), uint8_t{0});
    std::fill(fls_touched_.begin(), fls_touched_.end(), uint8_t{0});
    std::fill(ps_echoes_.begin(), ps_echoes_.end(), uint8_t{0});
    std::fill(above_seabed_votes_.begin(), above_seabed_votes_.end(), uint8_t{0});
    std::fill(ps_crossings_.begin(), ps_crossings_.end(), uint8_t{0});
}

void VoxelMap::release() {
    clear();
    origin_.setZero();
    initialised_ = false;
}

void VoxelMap::initialiseAt(const Eigen::Vector3d& centre) {
    clear();
    origin_ = centre - 0.5 * extent();
    if (snap_to_lattice_) origin_ = (origin_ / resolution_).array().round().matrix() * resolution_;
    initialised_ = true;
}

void VoxelMap::saveState(StateWriter& w) const {
    w.pod(static_cast<uint64_t>(log_odds_.size()));
    w.pod(static_cast<uint8_t>(initialised_));
    for (int i = 0; i < 3; ++i) w.pod(origin_[i]);
    if (!initialised_) return;  // an unanchored map is all zeros (release() and the constructor see to it)
    w.bytes(log_odds_.data(), log_odds_.size() * sizeof(float));
    // The flag byte as before the planes, so checkpoints keep their format.
    if (uint8_t* f = w.reserve(size())) copyFlagBytes(f);
    w.bytes(above_seabed_votes_.data(), above_seabed_votes_.size());
    w.bytes(ps_crossings_.data(), ps_crossings_.size());
}

bool VoxelMap::loadState(StateReader& r) {
    uint8_t init = 0;
    if (!r.expect(log_odds_.size()) || !r.pod(init)) return false;
    Eigen::Vector3d o;
    for (int i = 0; i < 3; ++i)
        if (!r.pod(o[i])) return false;
    if (!o.allFinite() || init > 1) return false;
    if (init == 0) {
        clear();
        origin_ = o;
        initialised_ = false;
        return true;
    }
    if (!r.bytes(log_odds_.data(), log_odds_.size() * sizeof(float))) return false;
    const uint8_t* f = r.view(log_odds_.size());
    if (f == nullptr) return false;
    for (std::size_t i = 0; i < log_odds_.size(); ++i) setFlags(i, f[i]);
    if (!r.bytes(above_seabed_votes_.data(), above_seabed_votes_.size()) ||
        !r.bytes(ps_crossings_.data(), ps_crossings_.size()))
        return false;
    for (float& l : log_odds_)  // never trust a value from disk to be inside the clamp
        if (!std::isfinite(l)) return false;
        else l = std::min(std::max(l, clamp_min_), clamp_max_);
    origin_ = o;
    initialised_ = init != 0;
    return true;
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
