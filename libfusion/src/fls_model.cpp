#include "sonarfusion/fls_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sonarfusion/beam_direction.hpp"

namespace sonarfusion {

namespace {
void require(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("FLS geometry: ") + what);
}
}  // namespace

FlsModel::FlsModel(const FlsGeometry& g)
    : rows_(g.rows), cols_(g.beams), nv_(g.elevation_samples), tilt_(g.tilt), elevation_min_(g.elevation_min),
      elevation_max_(g.elevation_max) {
    require(rows_ >= 2 && rows_ <= 16384, "rows must be in 2..16384");
    require(cols_ >= 1 && cols_ <= 4096, "beams must be in 1..4096");
    require(nv_ >= 1 && nv_ <= 256, "elevation_samples must be in 1..256");
    require(std::isfinite(g.range_min) && std::isfinite(g.range_max) && g.range_min >= 0.0 &&
                g.range_max > g.range_min,
            "need 0 <= range_min < range_max");
    require(std::isfinite(g.elevation_min) && std::isfinite(g.elevation_max) &&
                g.elevation_max >= g.elevation_min,
            "need elevation_min <= elevation_max");
    require(std::isfinite(g.tilt) && std::isfinite(g.fov_horizontal) && g.fov_horizontal > 0.0,
            "tilt and fov_horizontal must be finite, fov > 0");

    range_.resize(rows_);
    if (!g.row_range.empty()) {
        require(static_cast<int>(g.row_range.size()) == rows_, "row_range size must equal rows");
        for (int r = 0; r < rows_; ++r) {
            require(std::isfinite(g.row_range[r]) && g.row_range[r] >= 0.0, "row_range must be >= 0");
            range_[r] = g.row_range[r];
        }
    } else {
        // Eq. 1: row 0 is the farthest range.
        for (int r = 0; r < rows_; ++r)
            range_[r] = g.range_min + static_cast<double>(rows_ - 1 - r) / (rows_ - 1) * (g.range_max - g.range_min);
    }

    for (int r = 0; r < rows_; ++r) range_max_ = std::max(range_max_, range_[r]);

    bearing_.resize(cols_);
    if (!g.beam_bearing.empty()) {
        require(static_cast<int>(g.beam_bearing.size()) == cols_, "beam_bearing size must equal beams");
        for (int c = 0; c < cols_; ++c) {
            require(std::isfinite(g.beam_bearing[c]), "beam_bearing must be finite");
            bearing_[c] = g.beam_bearing[c];
        }
    } else {
        // Eq. 2: the centre column (w/2) is bearing 0, column 0 is port.
        for (int c = 0; c < cols_; ++c)
            bearing_[c] = g.fov_horizontal * (c - cols_ / 2.0) / cols_;
    }

    // Eq. 3.
    elevation_.resize(nv_);
    for (int k = 0; k < nv_; ++k)
        elevation_[k] = nv_ == 1 ? 0.5 * (g.elevation_min + g.elevation_max)
                                 : g.elevation_min + k * (g.elevation_max - g.elevation_min) / (nv_ - 1);

    // Eq. 4 without the range: (cos(t+phi) cos th, cos(t+phi) sin th, sin(t+phi)).
    direction_.resize(static_cast<std::size_t>(cols_) * nv_);
    for (int c = 0; c < cols_; ++c)
        for (int k = 0; k < nv_; ++k) direction_[static_cast<std::size_t>(c) * nv_ + k] = directionAt(c, elevation_[k]);
}

Eigen::Vector3f FlsModel::directionAt(int col, double elevation) const {
    return beamDirection(tilt_ + elevation, bearing_[col]).cast<float>();  // Eq. 4
}

bool FlsModel::frameMatches(const FlsFrame& f) const {
    return f.data != nullptr && f.rows == rows_ && f.cols == cols_ &&
           f.data_size == static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_);
}

}  // namespace sonarfusion
