// Bounded dense voxel grid of log-odds (paper 2.1-2.2, Eqs. 7-9), allocated
// once at construction; re-anchoring clears it in place.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/state_codec.hpp"

namespace sonarfusion {

struct VoxelIndex {
    int x = 0, y = 0, z = 0;
    bool operator==(const VoxelIndex& o) const { return x == o.x && y == o.y && z == o.z; }
};

// Eq. 9: occupancy probability from log-odds.
[[nodiscard]] inline float occupancyFromLogOdds(float l) { return 1.0f / (1.0f + std::exp(-l)); }
// Inverse of Eq. 9 (Eqs. 5 and 12 use it with P_o and P_f).
[[nodiscard]] inline double logOddsFromProbability(double p) { return std::log(p / (1.0 - p)); }

// The one lattice: voxel (x, y, z) of a grid nx wide and ny deep is element
// (z * ny + y) * nx + x (x fastest). Every grid in the project indexes by it.
[[nodiscard]] constexpr std::size_t latticeIndex(std::size_t x, std::size_t y, std::size_t z, std::size_t nx,
                                                 std::size_t ny) {
    return (z * ny + y) * nx + x;
}

class VoxelMap {
public:
    static constexpr uint8_t kPsObserved = 1u << 0;  // a PS ray crossed or ended here
    static constexpr uint8_t kFlsTouched = 1u << 1;  // an FLS candidate point fell here
    // Bits 2..7 count the PS echoes (end points of Eq. 11) that fell here,
    // saturating at kPsEchoMax, so a saved map keeps them in its flag byte.
    static constexpr int kPsEchoShift = 2;
    static constexpr uint8_t kPsEchoMax = 63;
    // Saturation of the per-voxel count of FLS frames whose vote the seabed
    // cannot explain (flsAboveSeabedVotes).
    static constexpr uint8_t kAboveSeabedVotesMax = 255;
    // Saturation of the per-voxel count of PS rays that crossed (carved) it.
    static constexpr uint8_t kPsCrossingsMax = 255;

    explicit VoxelMap(const MapConfig& cfg);

    // Clears every voxel and places the grid so that `centre` is its centre.
    void initialiseAt(const Eigen::Vector3d& centre);
    void clear();
    // Clears the map and marks it unanchored (a survey slot freed for reuse).
    void release();
    [[nodiscard]] bool initialised() const { return initialised_; }

    [[nodiscard]] int nx() const { return nx_; }
    [[nodiscard]] int ny() const { return ny_; }
    [[nodiscard]] int nz() const { return nz_; }
    [[nodiscard]] std::size_t size() const { return log_odds_.size(); }
    [[nodiscard]] double resolution() const { return resolution_; }
    // Bytes the per-voxel arrays hold (9 per voxel: 4 of log-odds, 5 byte planes).
    [[nodiscard]] std::size_t memoryBytes() const {
        return log_odds_.size() * sizeof(float) + ps_observed_.size() + fls_touched_.size() + ps_echoes_.size() +
               above_seabed_votes_.size() + ps_crossings_.size();
    }
    [[nodiscard]] const Eigen::Vector3d& origin() const { return origin_; }  // min corner
    [[nodiscard]] Eigen::Vector3d centre() const;
    [[nodiscard]] Eigen::Vector3d extent() const { return Eigen::Vector3d(nx_, ny_, nz_) * resolution_; }
    // Distance from p to the nearest point of the grid's box (0 inside it).
    [[nodiscard]] double distanceTo(const Eigen::Vector3d& p) const {
        const Eigen::Vector3d hi = origin_ + extent();
        return (origin_ - p).cwiseMax(p - hi).cwiseMax(Eigen::Vector3d::Zero()).norm();
    }

    [[nodiscard]] bool contains(const VoxelIndex& v) const {
        return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < nx_ && v.y < ny_ && v.z < nz_;
    }
    // False (and `out` untouched) when p is outside the grid or not finite.
    [[nodiscard]] bool worldToIndex(const Eigen::Vector3d& p, VoxelIndex& out) const;
    [[nodiscard]] Eigen::Vector3d centreOf(const VoxelIndex& v) const;
    [[nodiscard]] std::size_t linear(const VoxelIndex& v) const {
        return latticeIndex(static_cast<std::size_t>(v.x), static_cast<std::size_t>(v.y), static_cast<std::size_t>(v.z),
                            static_cast<std::size_t>(nx_), static_cast<std::size_t>(ny_));
    }
    [[nodiscard]] VoxelIndex fromLinear(std::size_t i) const;

    [[nodiscard]] float logOdds(std::size_t i) const { return log_odds_[i]; }
    [[nodiscard]] float occupancy(std::size_t i) const { return occupancyFromLogOdds(log_odds_[i]); }
    // The flag byte as saved (kPsObserved | kFlsTouched | echo count << kPsEchoShift).
    // Held as three byte planes, so the hot loops set a flag with a plain store
    // of 1 instead of a read-modify-write of a shared byte (docs/performance.md,
    // "Flags as byte planes").
    [[nodiscard]] uint8_t flags(std::size_t i) const {
        return static_cast<uint8_t>(ps_observed_[i] | (fls_touched_[i] << 1) | (ps_echoes_[i] << kPsEchoShift));
    }
    // flags(i) of every voxel into out[0, size()): the byte checkpoints and map files save.
    void copyFlagBytes(uint8_t* out) const {
        for (std::size_t i = 0; i < size(); ++i) out[i] = flags(i);
    }
    [[nodiscard]] bool psObserved(std::size_t i) const { return ps_observed_[i] != 0; }
    [[nodiscard]] bool flsTouched(std::size_t i) const { return fls_touched_[i] != 0; }
    [[nodiscard]] int psEchoCount(std::size_t i) const { return ps_echoes_[i]; }
    void addPsEcho(std::size_t i) { ps_echoes_[i] = static_cast<uint8_t>(ps_echoes_[i] + (ps_echoes_[i] < kPsEchoMax)); }

    // Frames in which an FLS return nearer than the seabed anywhere on its
    // beam's elevation arc voted this voxel: something stood above the seabed
    // on that arc (docs/algorithm.md, "Off-swath parts: votes the seabed cannot
    // explain"). Saturates at kAboveSeabedVotesMax (Writer::addAboveSeabedVote).
    [[nodiscard]] int flsAboveSeabedVotes(std::size_t i) const { return above_seabed_votes_[i]; }
    void setFlsAboveSeabedVotes(std::size_t i, uint8_t n) { above_seabed_votes_[i] = n; }

    // PS rays that crossed this voxel on the way to an echo farther out (the
    // rays Eq. 13 carves with, spared or not; UpdateConfig::ps_carve_spare_echo_share).
    // Saturates at kPsCrossingsMax. Checkpointed and saved in the map file.
    [[nodiscard]] int psCrossings(std::size_t i) const { return ps_crossings_[i]; }
    void setPsCrossings(std::size_t i, uint8_t n) { ps_crossings_[i] = n; }

    // Eqs. 6/13 followed by the clamp of Eqs. 7-8 (min/max compiles branch-free;
    // bounds first so it is maxss/minss without register copies, and a NaN
    // increment lands on clamp_min, docs/performance.md).
    void add(std::size_t i, float delta) {
        log_odds_[i] = std::min(clamp_max_, std::max(clamp_min_, log_odds_[i] + delta));
    }
    // Sets kPsObserved and/or kFlsTouched (other bits are ignored; the echo
    // count has addPsEcho). With a constant flag the tests fold away.
    void setFlag(std::size_t i, uint8_t flag) {
        if (flag & kPsObserved) ps_observed_[i] = 1;
        if (flag & kFlsTouched) fls_touched_[i] = 1;
    }

    // The same updates for hot loops: the data pointers and clamp bounds live
    // in locals, so the compiler need not reload them after every flag byte
    // store (a byte store may alias anything). Valid while the map lives.
    class Writer {
    public:
        explicit Writer(VoxelMap& m)
            : l_(m.log_odds_.data()), ps_observed_(m.ps_observed_.data()), fls_touched_(m.fls_touched_.data()),
              above_(m.above_seabed_votes_.data()),
              crossed_(m.ps_crossings_.data()), lo_(m.clamp_min_),
              hi_(m.clamp_max_) {}
        void add(std::size_t i, float delta) { l_[i] = std::min(hi_, std::max(lo_, l_[i] + delta)); }
        void setFlag(std::size_t i, uint8_t flag) {  // as VoxelMap::setFlag
            if (flag & kPsObserved) ps_observed_[i] = 1;
            if (flag & kFlsTouched) fls_touched_[i] = 1;
        }
        void addAboveSeabedVote(std::size_t i) { above_[i] = static_cast<uint8_t>(above_[i] + (above_[i] < kAboveSeabedVotesMax)); }
        void addPsCrossing(std::size_t i) { crossed_[i] = static_cast<uint8_t>(crossed_[i] + (crossed_[i] < kPsCrossingsMax)); }

    private:
        float* l_;
        uint8_t* ps_observed_;
        uint8_t* fls_touched_;
        uint8_t* above_;
        uint8_t* crossed_;
        float lo_, hi_;
    };
    [[nodiscard]] Writer writer() { return Writer(*this); }
    // Direct write, for loading a saved map; clamps like add().
    void setLogOdds(std::size_t i, float l) { log_odds_[i] = 0.0f; add(i, l); }
    void setFlags(std::size_t i, uint8_t f) {  // the whole byte, as flags() returns it
        ps_observed_[i] = f & kPsObserved;
        fls_touched_[i] = (f & kFlsTouched) >> 1;
        ps_echoes_[i] = static_cast<uint8_t>(f >> kPsEchoShift);
    }

    [[nodiscard]] float clampMin() const { return clamp_min_; }
    [[nodiscard]] float clampMax() const { return clamp_max_; }
    // Checkpoints: origin, anchoring, log-odds, flags, above-seabed votes and PS crossings (sizes must match).
    void saveState(StateWriter& w) const;
    [[nodiscard]] bool loadState(StateReader& r);
    [[nodiscard]] const std::vector<float>& logOddsData() const { return log_odds_; }
    [[nodiscard]] const std::vector<uint8_t>& aboveSeabedVotesData() const { return above_seabed_votes_; }
    [[nodiscard]] const std::vector<uint8_t>& psCrossingsData() const { return ps_crossings_; }

private:
    int nx_, ny_, nz_;
    double resolution_;
    float clamp_min_, clamp_max_;
    bool snap_to_lattice_;
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    bool initialised_ = false;
    std::vector<float> log_odds_;
    std::vector<uint8_t> ps_observed_;  // 0 or 1: kPsObserved
    std::vector<uint8_t> fls_touched_;  // 0 or 1: kFlsTouched
    std::vector<uint8_t> ps_echoes_;    // 0..kPsEchoMax
    std::vector<uint8_t> above_seabed_votes_;
    std::vector<uint8_t> ps_crossings_;
};

}  // namespace sonarfusion
