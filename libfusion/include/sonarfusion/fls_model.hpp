// FLS pixel -> candidate points (paper Eqs. 1-4). Ranges per row and unit
// directions per (column, elevation sample) are tabulated per geometry: a
// candidate point is range[row] * direction[col][k], no trig. A frame may carry
// its own geometry (per-ping, as fls_image_t does); the Mapper keeps the tables
// of a few geometries (assign(), MapperConfig::fls_max_geometries).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

// A borrowed view of one FLS image: rows x cols uint8, row-major, row 0 far.
struct FlsFrame {
    int64_t utime = 0;
    int rows = 0;
    int cols = 0;
    const uint8_t* data = nullptr;
    std::size_t data_size = 0;
    // Optional per-ping geometry, as fls_image_t carries it: one range per row
    // (m, row 0 farthest), one bearing per column (rad, column 0 port-most) and
    // the vertical aperture (rad). Null: the configured geometry (Eqs. 1-3).
    const float* row_range = nullptr;
    const float* beam_bearing = nullptr;
    double elevation_min = 0.0, elevation_max = 0.0;
    [[nodiscard]] bool hasGeometry() const { return row_range != nullptr || beam_bearing != nullptr; }
};

// The level above which a pixel of `f` is an echo rather than noise: the
// image's median plus `sigmas` robust standard deviations (1.4826 x the median
// absolute deviation), over every 7th pixel. Most of a sonar image is water or
// shadow, so the median and MAD are the noise's. No allocation (two 256-bin histograms).
[[nodiscard]] int noiseLevel(const FlsFrame& f, double sigmas);

// The nearest row (rows count from the far end, Eq. 1) of column `col` that
// could be a return: a pixel above
// `vote_threshold`, or the nearer of two consecutive pixels above
// `noise_level` (a lone noise pixel does not stop the search); -1 when none.
[[nodiscard]] inline int firstEchoRow(const FlsFrame& f, int col, int vote_threshold, int noise_level) {
    for (int row = f.rows - 1; row >= 0; --row) {
        const uint8_t v = f.data[static_cast<std::size_t>(row) * f.cols + col];
        if (v > vote_threshold) return row;
        if (v > noise_level && row > 0 && f.data[static_cast<std::size_t>(row - 1) * f.cols + col] > noise_level)
            return row;
    }
    return -1;
}

class FlsModel {
public:
    // Throws std::invalid_argument on an impossible geometry.
    explicit FlsModel(const FlsGeometry& g);

    [[nodiscard]] int rows() const { return rows_; }
    [[nodiscard]] int cols() const { return cols_; }
    [[nodiscard]] int elevationSamples() const { return nv_; }

    // Eq. 1 (or the per-row table of a non-uniform sonar).
    [[nodiscard]] double rangeOfRow(int row) const { return range_[row]; }
    // True when no row is farther than the row before it (Eq. 1's order; a
    // frame's own row ranges need not keep it): then rows can be searched by range.
    [[nodiscard]] bool rangesFallWithRow() const { return ranges_fall_; }
    // With ranges falling with the row: the last row whose range is at least
    // `range` (-1: none), by bisection.
    [[nodiscard]] int lastRowAtLeast(double range) const {
        int lo = 0, hi = rows_ - 1, found = -1;
        while (lo <= hi) {
            const int mid = (lo + hi) / 2;
            if (range_[mid] >= range) {
                found = mid;
                lo = mid + 1;
            } else {
                hi = mid - 1;
            }
        }
        return found;
    }
    // Eq. 2 (or the per-beam table).
    [[nodiscard]] double bearingOfColumn(int col) const { return bearing_[col]; }
    // Eq. 3.
    [[nodiscard]] double elevationOfSample(int k) const { return elevation_[k]; }
    // Unit direction of Eq. 4 in the sensor frame (tilt included).
    [[nodiscard]] const Eigen::Vector3f& direction(int col, int k) const {
        return direction_[static_cast<std::size_t>(col) * nv_ + k];
    }
    // Eq. 4: candidate point in the sensor frame.
    [[nodiscard]] Eigen::Vector3d pointInSensor(int row, int col, int k) const {
        return range_[row] * direction(col, k).cast<double>();
    }
    [[nodiscard]] const std::vector<Eigen::Vector3f>& directions() const { return direction_; }
    // Unit direction (sensor frame) of column `col` at any elevation inside the
    // aperture (Eq. 4 without the range), for arcs sampled finer than N_v.
    [[nodiscard]] Eigen::Vector3f directionAt(int col, double elevation) const;
    // directionAt(col, e) at the aperture's lower edge (0), its centre
    // 0.5 * (min + max) (1) and its upper edge (2), tabulated: the seabed
    // tests of every frame take them per beam (fls_detection.hpp).
    [[nodiscard]] const Eigen::Vector3f& edgeDirection(int col, int which) const {
        return edge_direction_[static_cast<std::size_t>(col) * 3 + static_cast<std::size_t>(which)];
    }
    [[nodiscard]] double elevationMin() const { return elevation_min_; }
    [[nodiscard]] double elevationMax() const { return elevation_max_; }
    [[nodiscard]] double rangeMax() const { return range_max_; }

    // True when the frame's size agrees with this geometry and its buffer.
    [[nodiscard]] bool frameMatches(const FlsFrame& f) const;

    // Per-ping geometry (docs/algorithm.md, "Per-ping FLS geometry").
    // True when the frame carries this model's geometry: same size, every range,
    // bearing and aperture limit equal up to float32 rounding.
    [[nodiscard]] bool sameGeometry(const FlsFrame& f) const;
    // Rebuilds the tables in place from the frame's own geometry (tilt and N_v
    // stay). False, and nothing changed, when the frame is larger than the
    // geometry this model was constructed with (its capacity): never allocates.
    [[nodiscard]] bool assign(const FlsFrame& f);
    [[nodiscard]] int rowCapacity() const { return row_capacity_; }
    [[nodiscard]] int colCapacity() const { return col_capacity_; }

private:
    void buildDirections();

    int rows_, cols_, nv_;
    int row_capacity_, col_capacity_;
    double tilt_, elevation_min_, elevation_max_, range_max_ = 0.0;
    bool ranges_fall_ = true;  // rangesFallWithRow
    std::vector<double> range_;
    std::vector<double> bearing_;
    std::vector<double> elevation_;
    std::vector<Eigen::Vector3f> direction_;  // cols * nv
    std::vector<Eigen::Vector3f> edge_direction_;  // cols * 3 (edgeDirection)
};

}  // namespace sonarfusion
