#include "sonarfusion/fls_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sonarfusion/beam_direction.hpp"
#include "sonarfusion/noise_level.hpp"

namespace sonarfusion {

namespace {
void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(std::string("FLS geometry: ") + what);
}
}  // namespace

FlsModel::FlsModel(const FlsGeometry& g)
    : rows_(g.rows), cols_(g.beams), nv_(g.elevation_samples), row_capacity_(g.rows), col_capacity_(g.beams), tilt_(g.tilt), elevation_min_(g.elevation_min),
      elevation_max_(g.elevation_max) {
    require(rows_ >= 2 && rows_ <= kMaxFlsRows, "rows must be in 2.." + std::to_string(kMaxFlsRows));
    require(cols_ >= 1 && cols_ <= kMaxFlsBeams, "beams must be in 1.." + std::to_string(kMaxFlsBeams));
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
    for (int r = 1; r < rows_; ++r) ranges_fall_ = ranges_fall_ && range_[r] <= range_[r - 1];

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

    elevation_.resize(nv_);
    direction_.resize(static_cast<std::size_t>(cols_) * nv_);
    edge_direction_.resize(static_cast<std::size_t>(cols_) * 3);
    buildDirections();
}

void FlsModel::buildDirections() {
    // Eq. 3.
    for (int k = 0; k < nv_; ++k)
        elevation_[k] = nv_ == 1 ? 0.5 * (elevation_min_ + elevation_max_)
                                 : elevation_min_ + k * (elevation_max_ - elevation_min_) / (nv_ - 1);
    // Eq. 4 without the range: (cos(t+phi) cos th, cos(t+phi) sin th, sin(t+phi)).
    for (int c = 0; c < cols_; ++c)
        for (int k = 0; k < nv_; ++k) direction_[static_cast<std::size_t>(c) * nv_ + k] = directionAt(c, elevation_[k]);
    const double edges[3] = {elevation_min_, 0.5 * (elevation_min_ + elevation_max_), elevation_max_};
    for (int c = 0; c < cols_; ++c)
        for (int e = 0; e < 3; ++e) edge_direction_[static_cast<std::size_t>(c) * 3 + e] = directionAt(c, edges[e]);
}

namespace {
// Equal up to the rounding of a float32 message field.
bool sameRange(double a, double b) { return std::fabs(a - b) <= 1e-5 * std::max(1.0, std::fabs(b)); }
bool sameAngle(double a, double b) { return std::fabs(a - b) <= 1e-6; }
}  // namespace

bool FlsModel::sameGeometry(const FlsFrame& f) const {
    if (f.rows != rows_ || f.cols != cols_ || !f.row_range || !f.beam_bearing) return false;
    if (!sameAngle(f.elevation_min, elevation_min_) || !sameAngle(f.elevation_max, elevation_max_)) return false;
    // The ends first: a changed window or beam set differs there.
    if (!sameRange(f.row_range[0], range_[0]) || !sameRange(f.row_range[rows_ - 1], range_[rows_ - 1]) ||
        !sameAngle(f.beam_bearing[0], bearing_[0]) || !sameAngle(f.beam_bearing[cols_ - 1], bearing_[cols_ - 1]))
        return false;
    for (int r = 0; r < rows_; ++r)
        if (!sameRange(f.row_range[r], range_[r])) return false;
    for (int c = 0; c < cols_; ++c)
        if (!sameAngle(f.beam_bearing[c], bearing_[c])) return false;
    return true;
}

bool FlsModel::assign(const FlsFrame& f) {
    if (!f.row_range || !f.beam_bearing || f.rows < 2 || f.cols < 1 || f.rows > row_capacity_ ||
        f.cols > col_capacity_)
        return false;
    rows_ = f.rows;
    cols_ = f.cols;
    range_.resize(rows_);  // within the capacity reserved at construction: no allocation
    bearing_.resize(cols_);
    direction_.resize(static_cast<std::size_t>(cols_) * nv_);
    edge_direction_.resize(static_cast<std::size_t>(cols_) * 3);
    range_max_ = 0.0;
    for (int r = 0; r < rows_; ++r) {
        range_[r] = f.row_range[r];
        range_max_ = std::max(range_max_, range_[r]);
    }
    ranges_fall_ = true;
    for (int r = 1; r < rows_; ++r) ranges_fall_ = ranges_fall_ && range_[r] <= range_[r - 1];
    for (int c = 0; c < cols_; ++c) bearing_[c] = f.beam_bearing[c];
    elevation_min_ = f.elevation_min;
    elevation_max_ = f.elevation_max;
    buildDirections();
    return true;
}

Eigen::Vector3f FlsModel::directionAt(int col, double elevation) const {
    return beamDirection(tilt_ + elevation, bearing_[col]).cast<float>();  // Eq. 4
}

bool FlsModel::frameMatches(const FlsFrame& f) const {
    return f.data != nullptr && f.rows == rows_ && f.cols == cols_ &&
           f.data_size == static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_);
}

int noiseLevel(const FlsFrame& f, double sigmas) {
    const std::size_t pixels = static_cast<std::size_t>(f.rows) * f.cols;
    if (pixels == 0 || f.data == nullptr) return 255;
    // Every 7th pixel (7 shares no factor with usual image widths, so every
    // row and column is sampled): thousands of samples pin a median to a count.
    constexpr std::size_t kStride = 7;
    IntensityHistogram hist{};
    std::size_t n = 0;
    for (std::size_t i = 0; i < pixels; i += kStride, ++n) ++hist[f.data[i]];
    return static_cast<int>(std::min(255.0, std::ceil(noiseLevelOf(hist, n, sigmas))));
}

}  // namespace sonarfusion
