// Paper 2.4: threshold the occupancy map, estimate the seabed per horizontal
// cell with a moving average, and report connected groups of voxels standing
// clearly above it as objects. All buffers are sized for the map once.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/voxel_map.hpp"

namespace sonarfusion {

struct ObjectInfo {
    int id = 0;  // 1-based label in objectLabel()
    int voxel_count = 0;
    double volume_m3 = 0.0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // NED
    Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();  // voxel bounds (outer faces)
    Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
    double height_m = 0.0;  // top of the object above the local seabed baseline
    // Its seed voxels were confirmed by PS echoes (the variants that require
    // confirmation); false where the FLS alone declared it (fls_only).
    bool ps_confirmed = false;
};

struct SegmentationStats {
    int occupied_voxels = 0;
    int candidate_voxels = 0;      // occupied, above the seabed surface, (PS-confirmed if required)
    int unconfirmed_voxels = 0;    // would be candidates but the PS never confirmed them
    int mirror_echo_voxels = 0;    // echo-confirmed, but the FLS saw nothing above the seabed there
    int water_above_echo_voxels = 0;  // crossed, echo-less, confirmed only by the layer below
    int crossed_water_voxels = 0;     // occupied below an object, crossed by the PS, no above-seabed FLS vote: not filled
    int objects = 0;
    int objects_dropped = 0;       // beyond max_objects
};

class Segmenter {
public:
    Segmenter(const SegmentationConfig& cfg, bool require_ps_observation, const VoxelMap& map);

    // Recomputes everything from the map; no allocation.
    const SegmentationStats& run(const VoxelMap& map);

    // Horizontal along-track axis (north, east; normalised here) for the
    // seabed moving average (paper 2.4). Zero, or never set: a square window.
    void setAlongTrack(const Eigen::Vector2d& north_east);
    [[nodiscard]] const Eigen::Vector2d& alongTrack() const { return along_track_; }

    [[nodiscard]] const std::vector<ObjectInfo>& objects() const { return objects_; }
    // Per voxel: 0, or the id of the object it belongs to.
    [[nodiscard]] int32_t objectLabel(std::size_t voxel) const { return label_[voxel]; }
    [[nodiscard]] bool occupied(std::size_t voxel) const { return occupied_[voxel] != 0; }
    // How an object voxel joined its object in the last run: the negated label
    // code of label() (1 a PS-confirmed seed or candidate, 2 a low candidate, 3 an
    // FLS-only extension, 4 straight down, 5 off-swath, 6 the seabed's own voxel,
    // 7 PS-crossed but outweighed, 8 unobserved below); 0 for other voxels. For
    // diagnosis (which rule put a false voxel in a map).
    [[nodiscard]] int joinClass(std::size_t voxel) const { return label_[voxel] > 0 ? join_class_[voxel] : 0; }
    // Seabed baseline depth (NED z, m) of column (ix, iy); NaN where unknown.
    [[nodiscard]] double seabedDepth(int ix, int iy) const { return baseline_[static_cast<std::size_t>(iy) * nx_ + ix]; }
    [[nodiscard]] const SegmentationStats& stats() const { return stats_; }
    // The echo count that confirmed a voxel's neighbourhood in the last run.
    [[nodiscard]] int echoThreshold() const { return echo_threshold_; }

private:
    void columnSurfaces(const VoxelMap& map);
    void echoSurfaces(const VoxelMap& map);
    [[nodiscard]] bool usableSurface(std::size_t col, double raise_limit) const;
    // The rise above the current baseline beyond which a column is left out of
    // the next fit (SegmentationConfig::seabed_raised_sigmas; at most min_object_height).
    [[nodiscard]] double raisedColumnThreshold(double resolution);
    void fitBaselinePlanes(const VoxelMap& map, double raise_limit);
    void lowerEnvelope(const VoxelMap& map);
    void smoothBaseline(const VoxelMap& map, double raise_limit);
    void smoothBaselineAlongTrack(int half, double raise_limit);
    [[nodiscard]] bool aboveBaseline(const VoxelMap& map, std::size_t voxel, double margin) const;
    // Whether a voxel beside c in its own layer (4-neighbourhood) is occupied.
    [[nodiscard]] bool besideOccupied(const VoxelMap& map, const VoxelIndex& c) const;
    [[nodiscard]] bool recedingFoot(const VoxelMap& map, const VoxelIndex& c, int dx, int dy) const;
    // low_layers_widen_where_seen: whether the low voxel n, one step (dx, dy)
    // across and one layer down from the object voxel c, shows the object widening.
    [[nodiscard]] bool footWidensAt(const VoxelMap& map, const VoxelIndex& c, const VoxelIndex& n, int dx, int dy) const;
    void markConfirmed(const VoxelMap& map);
    void dropWaterAboveEchoes(const VoxelMap& map);
    void dropMirrorEchoes(const VoxelMap& map);
    [[nodiscard]] bool confirmedByPs(const VoxelMap& map, std::size_t voxel) const;
    void label(const VoxelMap& map);

    SegmentationConfig cfg_;
    bool require_ps_;
    bool baseline_at_echo_centres_ = false;  // this run's baseline: echo voxel centres, not top faces
    bool crossings_counted_ = false;  // the map counts PS crossings (not an SFMAP001/002 file)
    bool above_seabed_counted_ = false;  // the map holds FLS above-seabed votes somewhere (the FLS mapped; not SFMAP001)
    int nx_, ny_, nz_;
    float logodds_threshold_;
    std::vector<uint8_t> occupied_;      // per voxel
    std::vector<uint8_t> confirmed_;     // per voxel: a PS echo within ps_echo_radius
    std::vector<int32_t> label_;         // per voxel
    std::vector<uint32_t> queue_;        // flood-fill queue, one slot per voxel
    std::vector<uint8_t> join_class_;    // per voxel: the label code (negated) it was joined by
    std::vector<int32_t> merged_into_;   // per object id: the id it joined (itself while it stands)
    std::vector<double> surface_;        // per column: depth of the seabed surface seen, NaN none
    std::vector<double> baseline_;       // per column: smoothed seabed depth
    std::vector<double> sat_sum_, sat_cnt_;  // summed-area tables, (nx+1)*(ny+1)
    std::vector<double> sat_plane_;          // 9 summed-area tables for local plane fits
    std::vector<double> eroded_, scratch_;   // per column, for the lower envelope
    std::vector<double> residual_;           // per column, for the residuals' scatter
    std::vector<uint8_t> column_ps_;         // per column: a PS ray reached one of its voxels
    std::vector<ObjectInfo> objects_;    // capacity max_objects
    SegmentationStats stats_;
    Eigen::Vector2d along_track_ = Eigen::Vector2d::Zero();  // unit (north, east), or zero
    int echo_threshold_ = 0;  // echoes that confirm, as found by the last run
};

}  // namespace sonarfusion
