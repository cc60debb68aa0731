// FLS pixel -> candidate points (paper Eqs. 1-4). The sensor geometry is fixed,
// so ranges per row and unit directions per (column, elevation sample) are
// tabulated once: a candidate point is range[row] * direction[col][k], no trig.
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
};

// The nearest row (rows count from the far end, Eq. 1) of column `col` whose
// intensity exceeds `threshold`: the beam's first return; -1 when it has none.
[[nodiscard]] inline int firstReturnRow(const FlsFrame& f, int col, int threshold) {
    for (int row = f.rows - 1; row >= 0; --row)
        if (f.data[static_cast<std::size_t>(row) * f.cols + col] > threshold) return row;
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
    [[nodiscard]] double elevationMin() const { return elevation_min_; }
    [[nodiscard]] double elevationMax() const { return elevation_max_; }
    [[nodiscard]] double rangeMax() const { return range_max_; }

    // True when the frame's size agrees with this geometry and its buffer.
    [[nodiscard]] bool frameMatches(const FlsFrame& f) const;

private:
    int rows_, cols_, nv_;
    double tilt_, elevation_min_, elevation_max_, range_max_ = 0.0;
    std::vector<double> range_;
    std::vector<double> bearing_;
    std::vector<double> elevation_;
    std::vector<Eigen::Vector3f> direction_;  // cols * nv
};

}  // namespace sonarfusion
