#include "sonarfusion/segmentation.hpp"

#include "sonarfusion/robust_scatter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

namespace sonarfusion {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kNoRaiseLimit = std::numeric_limits<double>::infinity();  // usableSurface: keep every column

// No update ever reached the voxel: log-odds at the prior, no flag.
bool neverUpdated(const VoxelMap& map, std::size_t i) { return map.logOdds(i) == 0.0f && map.flags(i) == 0; }
}

Segmenter::Segmenter(const SegmentationConfig& cfg, bool require_ps_observation, const VoxelMap& map)
    : cfg_(cfg), require_ps_(require_ps_observation), nx_(map.nx()), ny_(map.ny()), nz_(map.nz()) {
    if (!(cfg.occupied_probability > 0.0 && cfg.occupied_probability < 1.0))
        throw std::invalid_argument("segmentation: occupied_probability must be in (0, 1)");
    if (cfg.max_objects < 1 || cfg.min_object_voxels < 1 || !(cfg.baseline_window > 0.0))
        throw std::invalid_argument("segmentation: max_objects, min_object_voxels, baseline_window must be positive");
    logodds_threshold_ = static_cast<float>(logOddsFromProbability(cfg.occupied_probability));
    occupied_.assign(map.size(), 0);
    if (require_ps_ && cfg.ps_echo_radius >= 0) confirmed_.assign(map.size(), 0);
    label_.assign(map.size(), 0);
    queue_.assign(map.size(), 0);
    join_class_.assign(map.size(), 0);
    merged_into_.assign(static_cast<std::size_t>(cfg.max_objects) + 2, 0);
    const std::size_t cols = static_cast<std::size_t>(nx_) * ny_;
    surface_.assign(cols, kNaN);
    baseline_.assign(cols, kNaN);
    sat_sum_.assign(static_cast<std::size_t>(nx_ + 1) * (ny_ + 1), 0.0);
    sat_cnt_.assign(sat_sum_.size(), 0.0);
    if (cfg.seabed_from_ps_echoes) sat_plane_.assign(9 * sat_sum_.size(), 0.0);
    if (cfg.seabed_from_ps_echoes && cfg.seabed_from_lower_envelope) {
        eroded_.assign(cols, kNaN);
        scratch_.assign(cols, kNaN);
    }
    if (cfg.seabed_from_ps_echoes && cfg.seabed_raised_sigmas > 0.0) residual_.assign(cols, 0.0);
    if (cfg.fill_below_objects && cfg.fill_below_through_unobserved && cfg.fill_below_widens_through_unobserved)
        column_ps_.assign(cols, 0);
    objects_.reserve(cfg.max_objects);
}

// Per column, the seabed surface is the top of the lowest run of occupied
// voxels: the FLS votes below the seabed (which no PS ray can carve) stay part
// of that run, the surface on top of it is what the sensors saw.
void Segmenter::columnSurfaces(const VoxelMap& map) {
    const double res = map.resolution();
    const std::size_t layer = static_cast<std::size_t>(nx_) * ny_;
    for (int iy = 0; iy < ny_; ++iy) {
        for (int ix = 0; ix < nx_; ++ix) {
            const std::size_t col = static_cast<std::size_t>(iy) * nx_ + ix;
            int iz = nz_ - 1;  // NED: the largest z index is the deepest
            while (iz >= 0 && !occupied_[iz * layer + col]) --iz;
            if (iz < 0) {
                surface_[col] = kNaN;
                continue;
            }
            while (iz - 1 >= 0 && occupied_[(iz - 1) * layer + col]) --iz;
            surface_[col] = map.origin().z() + iz * res;  // top face of the voxel
        }
    }
}

// A column's surface enters the seabed fit when it is known and does not
// stand above the previous baseline by more than raise_limit (m; kNoRaiseLimit
// keeps every column), so an object does not lift the seabed under itself.
bool Segmenter::usableSurface(std::size_t col, double raise_limit) const {
    const double s = surface_[col];
    return !std::isnan(s) && !(!std::isnan(baseline_[col]) && s < baseline_[col] - raise_limit);
}

// The columns' echo heights scatter about the seabed by its relief and the
// height field's voxel steps; a column standing out of that scatter holds an
// object's echoes, if only some of them. Robust: the objects' own columns are
// outliers of the residuals, not part of their spread.
double Segmenter::raisedColumnThreshold(double resolution) {
    if (!(cfg_.seabed_raised_sigmas > 0.0)) return cfg_.min_object_height;
    std::size_t n = 0;
    for (std::size_t col = 0; col < surface_.size(); ++col)
        if (!std::isnan(surface_[col]) && !std::isnan(baseline_[col])) residual_[n++] = surface_[col] - baseline_[col];
    if (n < 3) return cfg_.min_object_height;
    const double median = medianInPlace(residual_, n);
    const double sigma = robustSigmaInPlace(residual_, n, median);
    return std::min(cfg_.min_object_height, std::max(0.5 * resolution, cfg_.seabed_raised_sigmas * sigma));
}

// Per column, the mean height of the PS echoes that ended in it (each voxel
// weighted by its echo count): the mean of those voxels' centres, where the
// echoes were to within a voxel (seabed_at_echo_centres), or of their top faces
// like columnSurfaces (the earlier rule, half a voxel shallower).
void Segmenter::echoSurfaces(const VoxelMap& map) {
    const double res = map.resolution();
    const std::size_t layer = static_cast<std::size_t>(nx_) * ny_;
    for (std::size_t col = 0; col < layer; ++col) {
        double sum = 0.0;
        int n = 0;
        for (int iz = 0; iz < nz_; ++iz) {
            const int e = map.psEchoCount(iz * layer + col);
            sum += e * (iz + 0.5);
            n += e;
        }
        const double offset = cfg_.seabed_at_echo_centres ? 0.0 : 0.5;
        surface_[col] = n > 0 ? map.origin().z() + (sum / n - offset) * res : kNaN;
    }
}

namespace {
// One pass of a sliding-window extreme over the known values (NaN: none), along
// x (step 1, lines of nx) or along y (step nx, lines of ny): out = the deepest
// (deepest = true) or shallowest value within `half` cells; NaN where the
// window holds none.
void lineExtreme(const std::vector<double>& in, std::vector<double>& out, int nx, int ny, int half, bool deepest,
                 bool along_y) {
    const int len = along_y ? ny : nx, lines = along_y ? nx : ny;
    const std::size_t step = along_y ? static_cast<std::size_t>(nx) : 1, line_step = along_y ? 1 : static_cast<std::size_t>(nx);
    for (int line = 0; line < lines; ++line) {
        const std::size_t base = static_cast<std::size_t>(line) * line_step;
        for (int i = 0; i < len; ++i) {
            double v = kNaN;
            for (int j = std::max(0, i - half); j <= std::min(len - 1, i + half); ++j) {
                const double s = in[base + static_cast<std::size_t>(j) * step];
                if (!std::isnan(s) && (std::isnan(v) || (deepest ? s > v : s < v))) v = s;
            }
            out[base + static_cast<std::size_t>(i) * step] = v;
        }
    }
}

// A square-window extreme: along x into tmp, then along y into out.
void windowExtreme(const std::vector<double>& in, std::vector<double>& tmp, std::vector<double>& out, int nx, int ny,
                   int half, bool deepest) {
    lineExtreme(in, tmp, nx, ny, half, deepest, false);
    lineExtreme(tmp, out, nx, ny, half, deepest, true);
}
}  // namespace

// The lower envelope of the column surfaces, as the first baseline: a
// morphological opening (the deepest surface within the window, then the
// shallowest of those within the window), both taken at the columns that hold
// a surface only. It removes whatever is narrower than the window and stands
// above the seabed, follows a plane exactly, and keeps a single low outlier to
// its own column (an opening never widens a pit). The ground filters of
// airborne lidar start the same way (Zhang et al. 2003, progressive
// morphological filter).
void Segmenter::lowerEnvelope(const VoxelMap& map) {
    const int half = std::max(1, static_cast<int>(std::lround(0.5 * cfg_.baseline_window / map.resolution())));
    windowExtreme(surface_, scratch_, eroded_, nx_, ny_, half, true);
    for (std::size_t col = 0; col < surface_.size(); ++col)
        if (std::isnan(surface_[col])) eroded_[col] = kNaN;
    windowExtreme(eroded_, scratch_, baseline_, nx_, ny_, half, false);
}

// The seabed under each column: a plane fitted by least squares to the column
// surfaces in the square window around it (nine summed-area tables keep it
// O(columns)), evaluated at the column. A plane follows a slope, which a
// moving average only does where the window is full. Columns standing above
// the previous baseline by more than raise_limit are left out (usableSurface).
void Segmenter::fitBaselinePlanes(const VoxelMap& map, double raise_limit) {
    const int half = std::max(1, static_cast<int>(std::lround(0.5 * cfg_.baseline_window / map.resolution())));
    const int w = nx_ + 1;
    const std::size_t plane = static_cast<std::size_t>(w) * (ny_ + 1);
    auto table = [&](int k, int x, int y) -> double& { return sat_plane_[k * plane + static_cast<std::size_t>(y) * w + x]; };
    double total_sum = 0.0, total_cnt = 0.0;
    for (int iy = 0; iy < ny_; ++iy) {
        double row[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        for (int ix = 0; ix < nx_; ++ix) {
            const std::size_t col = static_cast<std::size_t>(iy) * nx_ + ix;
            const double s = surface_[col];
            const bool use = usableSurface(col, raise_limit);
            if (use) {
                const double x = ix, y = iy;
                const double v[9] = {1.0, x, y, s, x * x, x * y, y * y, x * s, y * s};
                for (int k = 0; k < 9; ++k) row[k] += v[k];
                total_sum += s;
                total_cnt += 1.0;
            }
            for (int k = 0; k < 9; ++k) table(k, ix + 1, iy + 1) = table(k, ix + 1, iy) + row[k];
        }
    }
    const double global = total_cnt > 0.0 ? total_sum / total_cnt : kNaN;
    for (int iy = 0; iy < ny_; ++iy) {
        const int y0 = std::max(0, iy - half), y1 = std::min(ny_, iy + half + 1);
        for (int ix = 0; ix < nx_; ++ix) {
            const int x0 = std::max(0, ix - half), x1 = std::min(nx_, ix + half + 1);
            double m[9];
            for (int k = 0; k < 9; ++k)
                m[k] = table(k, x1, y1) - table(k, x1, y0) - table(k, x0, y1) + table(k, x0, y0);
            const double n = m[0];
            double value = global;
            if (n >= 3.0) {
                // Normal equations of z = a + b (x - xm) + c (y - ym), centred on
                // the window's mean column; a small ridge keeps a line of
                // columns (a narrow swath) from tilting the plane across it.
                const double xm = m[1] / n, ym = m[2] / n, zm = m[3] / n;
                Eigen::Matrix2d a;
                a << m[4] - n * xm * xm, m[5] - n * xm * ym, m[5] - n * xm * ym, m[6] - n * ym * ym;
                a += Eigen::Matrix2d::Identity() * (0.25 * n);
                const Eigen::Vector2d b(m[7] - n * xm * zm, m[8] - n * ym * zm);
                const Eigen::Vector2d g = a.ldlt().solve(b);
                value = zm + g.x() * (ix - xm) + g.y() * (iy - ym);
            } else if (n > 0.5) {
                value = m[3] / n;
            }
            baseline_[static_cast<std::size_t>(iy) * nx_ + ix] = value;
        }
    }
}

// Moving average of the column surfaces over a square window (summed-area
// tables keep it O(columns)). Columns standing above the previous baseline by
// more than raise_limit are left out (usableSurface).
void Segmenter::smoothBaseline(const VoxelMap& map, double raise_limit) {
    const int half = std::max(1, static_cast<int>(std::lround(0.5 * cfg_.baseline_window / map.resolution())));
    if (cfg_.baseline_along_track && along_track_.squaredNorm() > 0.0) {
        smoothBaselineAlongTrack(half, raise_limit);
        return;
    }
    const int w = nx_ + 1;
    double total_sum = 0.0, total_cnt = 0.0;
    for (int iy = 0; iy < ny_; ++iy) {
        double row_sum = 0.0, row_cnt = 0.0;
        for (int ix = 0; ix < nx_; ++ix) {
            const std::size_t col = static_cast<std::size_t>(iy) * nx_ + ix;
            const double s = surface_[col];
            const bool use = usableSurface(col, raise_limit);
            if (use) {
                row_sum += s;
                row_cnt += 1.0;
            }
            sat_sum_[(iy + 1) * w + ix + 1] = sat_sum_[iy * w + ix + 1] + row_sum;
            sat_cnt_[(iy + 1) * w + ix + 1] = sat_cnt_[iy * w + ix + 1] + row_cnt;
        }
        total_sum += row_sum;
        total_cnt += row_cnt;
    }
    const double global = total_cnt > 0.0 ? total_sum / total_cnt : kNaN;
    for (int iy = 0; iy < ny_; ++iy) {
        const int y0 = std::max(0, iy - half), y1 = std::min(ny_, iy + half + 1);
        for (int ix = 0; ix < nx_; ++ix) {
            const int x0 = std::max(0, ix - half), x1 = std::min(nx_, ix + half + 1);
            const double sum = sat_sum_[y1 * w + x1] - sat_sum_[y0 * w + x1] - sat_sum_[y1 * w + x0] + sat_sum_[y0 * w + x0];
            const double cnt = sat_cnt_[y1 * w + x1] - sat_cnt_[y0 * w + x1] - sat_cnt_[y1 * w + x0] + sat_cnt_[y0 * w + x0];
            baseline_[static_cast<std::size_t>(iy) * nx_ + ix] = cnt > 0.5 ? sum / cnt : global;
        }
    }
}

// Paper 2.4: the moving average runs along the track. Beside a straight pass
// the FLS and the PS see the seabed differently from the centre of the swath
// (FLS elevation arcs the PS seldom carves), so averaging across the track mixes
// two different apparent seabeds; along the track the apparent seabed of one
// lateral offset is averaged with itself.
void Segmenter::smoothBaselineAlongTrack(int half, double raise_limit) {
    // Stage the usable column surfaces (NaN: not used) in sat_sum_, which holds
    // at least one slot per column.
    double total_sum = 0.0, total_cnt = 0.0;
    for (std::size_t col = 0; col < surface_.size(); ++col) {
        const double s = surface_[col];
        const bool use = usableSurface(col, raise_limit);
        sat_sum_[col] = use ? s : kNaN;
        if (use) {
            total_sum += s;
            total_cnt += 1.0;
        }
    }
    const double global = total_cnt > 0.0 ? total_sum / total_cnt : kNaN;
    const double dx = along_track_.x(), dy = along_track_.y();
    for (int iy = 0; iy < ny_; ++iy) {
        for (int ix = 0; ix < nx_; ++ix) {
            double sum = 0.0;
            int cnt = 0;
            for (int k = -half; k <= half; ++k) {
                const int x = ix + static_cast<int>(std::lround(k * dx));
                const int y = iy + static_cast<int>(std::lround(k * dy));
                if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
                const double v = sat_sum_[static_cast<std::size_t>(y) * nx_ + x];
                if (std::isnan(v)) continue;
                sum += v;
                ++cnt;
            }
            baseline_[static_cast<std::size_t>(iy) * nx_ + ix] = cnt > 0 ? sum / cnt : global;
        }
    }
}

void Segmenter::setAlongTrack(const Eigen::Vector2d& north_east) {
    const double n = north_east.norm();
    along_track_ = std::isfinite(n) && n > 1e-9 ? Eigen::Vector2d(north_east / n) : Eigen::Vector2d::Zero();
}

// Echo confirmation: every voxel within ps_echo_radius (Chebyshev) of a voxel
// holding a PS echo end point. PS rays that only cross a voxel carve it
// (Eq. 13); a voxel they crossed a few times while the FLS voted it every frame
// is not something the PS saw.
// Whether voxel i's centre lies more than `margin` above its column's seabed
// baseline (NED: shallower); false where the baseline is unknown (NaN).
bool Segmenter::aboveBaseline(const VoxelMap& map, std::size_t i, double margin) const {
    const std::size_t layer = static_cast<std::size_t>(nx_) * ny_;
    const double centre_z = map.origin().z() + (static_cast<double>(i / layer) + 0.5) * map.resolution();
    return centre_z < baseline_[i % layer] - margin;
}

void Segmenter::markConfirmed(const VoxelMap& map) {
    std::fill(confirmed_.begin(), confirmed_.end(), 0);
    const int r = cfg_.ps_echo_radius;
    echo_threshold_ = cfg_.ps_echo_min_count;
    // Echoes summed over each voxel's neighbourhood (label_ is free scratch
    // until label() runs): a surface the PS saw at grazing incidence, or a
    // vertical face, spreads its echoes over several voxels, each holding few.
    std::fill(label_.begin(), label_.end(), 0);
    for (std::size_t i = 0; i < map.size(); ++i) {
        const int e = map.psEchoCount(i);
        if (e == 0) continue;
        const VoxelIndex c = map.fromLinear(i);
        for (int z = std::max(0, c.z - r); z <= std::min(nz_ - 1, c.z + r); ++z)
            for (int y = std::max(0, c.y - r); y <= std::min(ny_ - 1, c.y + r); ++y)
                for (int x = std::max(0, c.x - r); x <= std::min(nx_ - 1, c.x + r); ++x)
                    label_[map.linear({x, y, z})] += e;
    }
    // The threshold: a share of what a well-seen surface collects in this map
    // (90th percentile of the non-zero sums; queue_ is scratch here too). The
    // surfaces that count are those standing above the seabed by more than the
    // object height (ps_echo_reference_above_seabed): the scatter this
    // threshold rejects comes from the object's own echoes, and the seabed,
    // swept by every ping, collects far more than an object seen for a moment
    // (or far less than one seen from every pass). None: every surface counts.
    if (cfg_.ps_echo_min_fraction > 0.0) {
        std::size_t n = 0;
        if (cfg_.ps_echo_reference_above_seabed) {
            for (std::size_t i = 0; i < map.size(); ++i)
                if (label_[i] > 0 && aboveBaseline(map, i, cfg_.min_object_height))
                    queue_[n++] = static_cast<uint32_t>(label_[i]);
        }
        if (n == 0)
            for (std::size_t i = 0; i < map.size(); ++i)
                if (label_[i] > 0) queue_[n++] = static_cast<uint32_t>(label_[i]);
        if (n > 0) {
            const auto p90 = queue_.begin() + static_cast<std::ptrdiff_t>((9 * n) / 10);
            std::nth_element(queue_.begin(), p90, queue_.begin() + static_cast<std::ptrdiff_t>(n));
            echo_threshold_ = std::max(cfg_.ps_echo_min_count,
                                       static_cast<int>(std::ceil(cfg_.ps_echo_min_fraction * *p90)));
        }
    }
    for (std::size_t i = 0; i < map.size(); ++i) confirmed_[i] = label_[i] >= echo_threshold_ ? 1 : 0;
    if (cfg_.ps_crossed_confirmed_from_level_or_above) dropWaterAboveEchoes(map);
    if (cfg_.ps_echo_seen_above_seabed) dropMirrorEchoes(map);
}

// SegmentationConfig::ps_crossed_confirmed_from_level_or_above: PS rays crossed
// the voxel and none ended in it, so they went on to a surface beyond; when only
// the echoes of the layer below it reach the threshold, that surface is under
// it and the voxel is the water above it (NED: the layer below is c.z + 1).
void Segmenter::dropWaterAboveEchoes(const VoxelMap& map) {
    const int r = cfg_.ps_echo_radius;
    for (std::size_t i = 0; i < map.size(); ++i) {
        // Only occupied voxels can become object voxels (label()), so only theirs matters.
        if (!confirmed_[i] || !occupied_[i] || !map.psObserved(i) || map.psEchoCount(i) > 0) continue;
        const VoxelIndex c = map.fromLinear(i);
        int level_or_above = 0;
        for (int z = std::max(0, c.z - r); z <= c.z; ++z)
            for (int y = std::max(0, c.y - r); y <= std::min(ny_ - 1, c.y + r); ++y)
                for (int x = std::max(0, c.x - r); x <= std::min(nx_ - 1, c.x + r); ++x)
                    level_or_above += map.psEchoCount(map.linear({x, y, z}));
        if (level_or_above < echo_threshold_) {
            confirmed_[i] = 0;
            ++stats_.water_above_echo_voxels;
        }
    }
}

// SegmentationConfig::ps_echo_seen_above_seabed: a confirmed voxel whose
// neighbourhood the FLS voted, with no vote there from a return nearer than the
// seabed, holds echoes the PS could have placed from the other side of its fan.
void Segmenter::dropMirrorEchoes(const VoxelMap& map) {
    bool counted = false;  // an SFMAP001 map, or no seabed fit: nothing to judge by
    for (std::size_t i = 0; i < map.size() && !counted; ++i) counted = map.flsAboveSeabedVotes(i) > 0;
    if (!counted) return;
    const int r = cfg_.ps_echo_radius;
    for (std::size_t i = 0; i < map.size(); ++i) {
        if (!confirmed_[i]) continue;
        const VoxelIndex c = map.fromLinear(i);
        bool voted = false, above = false;
        for (int z = std::max(0, c.z - r); z <= std::min(nz_ - 1, c.z + r) && !above; ++z)
            for (int y = std::max(0, c.y - r); y <= std::min(ny_ - 1, c.y + r) && !above; ++y)
                for (int x = std::max(0, c.x - r); x <= std::min(nx_ - 1, c.x + r) && !above; ++x) {
                    const std::size_t n = map.linear({x, y, z});
                    voted = voted || map.flsTouched(n);
                    above = map.flsAboveSeabedVotes(n) > 0;
                }
        if (voted && !above) {
            confirmed_[i] = 0;
            ++stats_.mirror_echo_voxels;
        }
    }
}

bool Segmenter::confirmedByPs(const VoxelMap& map, std::size_t voxel) const {
    if (!require_ps_) return true;
    if (confirmed_.empty()) return map.psObserved(voxel);
    return confirmed_[voxel] != 0;
}

bool Segmenter::besideOccupied(const VoxelMap& map, const VoxelIndex& c) const {
    constexpr int kSide[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& d : kSide) {
        const VoxelIndex n{c.x + d[0], c.y + d[1], c.z};
        if (map.contains(n) && occupied_[map.linear(n)]) return true;
    }
    return false;
}

// base_follows_sloped_faces: c, above the seabed's own voxel, is the foot of a
// face that recedes upward in the direction (-dx, -dy) one voxel per layer over
// three layers (0.3 m of face at 0.1 m voxels): the voxels k layers up and k
// steps back (k = 1, 2, 3) are occupied, and nothing occupied stands on c or on
// the first two of them. The face then slopes on down and out through the
// seabed voxel (c + dx, dy, +1). A diagonal step needs the same along x and
// along y: a sloped side that ends at a vertical end face recedes diagonally at
// the corner, but the end does not slope. A vertical wall, a rounded body's
// undercut foot and a bar's blurred end (the frame's crossbars, 0.35 m) make no
// such staircase.
bool Segmenter::recedingFoot(const VoxelMap& map, const VoxelIndex& c, int dx, int dy) const {
    if (c.z < 3 || !aboveBaseline(map, map.linear(c), 0.5 * map.resolution())) return false;
    const auto staircase = [&](int sx, int sy) {
        if (!map.contains({c.x - 3 * sx, c.y - 3 * sy, c.z - 3})) return false;  // the far end; x, y monotone
        for (int k = 0; k < 3; ++k) {
            const VoxelIndex step{c.x - k * sx, c.y - k * sy, c.z - k};
            const VoxelIndex next{step.x - sx, step.y - sy, step.z - 1};
            if (occupied_[map.linear({step.x, step.y, step.z - 1})] || !occupied_[map.linear(next)]) return false;
        }
        return true;
    };
    return staircase(dx, dy) && (dx == 0 || dy == 0 || (staircase(dx, 0) && staircase(0, dy)));
}

bool Segmenter::footWidensAt(const VoxelMap& map, const VoxelIndex& c, const VoxelIndex& n, int dx, int dy) const {
    // The FLS saw it nearer than the seabed could return.
    if (map.flsAboveSeabedVotes(map.linear(n)) >= std::max(1, cfg_.fls_above_seabed_min_votes)) return true;
    // The face recedes upward at c: nothing on c, the object one step back over it.
    const VoxelIndex on{c.x, c.y, c.z - 1}, back{c.x - dx, c.y - dy, c.z - 1};
    return map.contains(on) && map.contains(back) && !occupied_[map.linear(on)] && occupied_[map.linear(back)];
}

void Segmenter::label(const VoxelMap& map) {
    const double res = map.resolution();
    const std::size_t layer = static_cast<std::size_t>(nx_) * ny_;
    // The columns some PS ray reached (fill_below_widens_through_unobserved),
    // in a map the FLS updated too: without the FLS's free space, the water
    // beside an object that only it would have seen is unobserved as well
    // (carve_only), and no update reaching a voxel says nothing of a shadow.
    if (!column_ps_.empty()) {
        std::fill(column_ps_.begin(), column_ps_.end(), 0);
        bool fls_mapped = false;
        for (std::size_t i = 0; i < map.size(); ++i) {
            fls_mapped = fls_mapped || map.flsTouched(i);
            if (map.psObserved(i)) column_ps_[i % layer] = 1;
        }
        if (!fls_mapped) std::fill(column_ps_.begin(), column_ps_.end(), 0);
    }
    // Candidates: occupied, above the seabed surface, PS-observed if required.
    // Label -1 marks those clearly above it (min_object_height), which may seed
    // an object; -2 those between the surface and that height, which may only
    // join one (hysteresis: an object keeps its lowest layers).
    for (std::size_t i = 0; i < map.size(); ++i) {
        label_[i] = 0;
        if (!occupied_[i]) {
            // A voxel no update ever reached (prior log-odds, no flag) lies in
            // the shadow of what is above it: below an object, its body. The
            // fill below may pass through it (fill_below_through_unobserved),
            // in a column the PS swept also widening (-8,
            // fill_below_widens_through_unobserved).
            if (cfg_.fill_below_objects && cfg_.fill_below_through_unobserved && neverUpdated(map, i) &&
                aboveBaseline(map, i, -0.5 * res))
                label_[i] = !column_ps_.empty() && column_ps_[i % layer] ? -8 : -4;
            continue;
        }
        // The voxel the seabed surface runs through (its box holds the
        // baseline, wherever in it) is the object's base where an object stands
        // on it, and seabed everywhere else: it joins only straight down. An
        // object resting on a surface inside that voxel reaches into it.
        const bool holds_seabed = baseline_at_echo_centres_ && aboveBaseline(map, i, -0.5 * res) &&
                                  !aboveBaseline(map, i, 0.5 * res);
        if (holds_seabed) {
            if (cfg_.fill_below_objects) label_[i] = cfg_.base_follows_sloped_faces ? -6 : -4;
            continue;
        }
        if (!aboveBaseline(map, i, 0.0)) continue;
        if (!confirmedByPs(map, i)) {
            ++stats_.unconfirmed_voxels;
            // Where no PS ray ever went, the FLS (with its own free space) is
            // the only evidence: such voxels may extend an object (-3), never seed one.
            // With FLS votes the seabed cannot explain (enough to be occupied
            // on those alone), they join an object from any side (-5).
            // With fls_only_needs_support, not over a voxel a sensor saw as
            // water (the next layer down, NED i + layer): that vote floats.
            const bool floats = cfg_.fls_only_needs_support && i + layer < map.size() && map.logOdds(i + layer) < 0.0f;
            // With low_echoes_seen_above_seabed, so do low voxels holding PS
            // echoes of their own, too few to confirm them: both sensors saw a
            // surface there, each below its own bar.
            const bool seen_above = cfg_.fls_above_seabed_min_votes > 0 &&
                                    map.flsAboveSeabedVotes(i) >= cfg_.fls_above_seabed_min_votes && !floats;
            const bool low_echoed = cfg_.low_echoes_seen_above_seabed && map.psEchoCount(i) > 0 &&
                                    !aboveBaseline(map, i, cfg_.min_object_height);
            // With fls_votes_per_ps_crossing, so do voxels PS rays crossed
            // with no echo of their own, when the FLS's votes outweigh those
            // crossings in the updates' own log-odds (-7: the clamp hid it),
            // up to the object's highest PS-confirmed layer, no higher.
            const bool outweighed =
                crossings_counted_ && cfg_.fls_votes_per_ps_crossing > 0.0 && map.psEchoCount(i) == 0 &&
                map.flsAboveSeabedVotes(i) > cfg_.fls_votes_per_ps_crossing * map.psCrossings(i);
            if (seen_above && (!map.psObserved(i) || low_echoed)) label_[i] = -5;
            else if (seen_above && outweighed) label_[i] = -7;
            else if (cfg_.fls_only_extension > 0 && !confirmed_.empty() && !map.psObserved(i)) label_[i] = -3;
            else if (cfg_.fill_below_objects) {
                // With fill_below_not_through_crossed_water: not where the PS
                // saw through and the FLS saw nothing the seabed cannot explain.
                // The layer on the seabed's own voxel is exempt: PS rays that end on
                // the seabed beside an object's foot cross it within the fan's
                // thickness (2 deg: 5-9 cm at 3-5 m, about a voxel).
                const bool crossed_water = cfg_.fill_below_not_through_crossed_water && crossings_counted_ &&
                                           above_seabed_counted_ && map.psCrossings(i) > 0 &&
                                           map.flsAboveSeabedVotes(i) == 0 && aboveBaseline(map, i, 1.5 * res);
                if (crossed_water) ++stats_.crossed_water_voxels;
                else label_[i] = -4;
            }
            continue;
        }
        label_[i] = aboveBaseline(map, i, cfg_.min_object_height) ? -1 : -2;
        ++stats_.candidate_voxels;
    }
    // 26-connected flood fill. Each voxel keeps the code it was joined by
    // (join_class_), so a later flood that reaches it can ask the same rule
    // (join_touching_floods).
    const bool join = cfg_.join_touching_floods;
    constexpr int32_t kDropped = -9;  // a group too small (or beyond max_objects): later floods may take it
    const auto root = [this](int id) {
        while (merged_into_[id] != id) id = merged_into_[id] = merged_into_[merged_into_[id]];
        return id;
    };
    // Folds object `from`'s sums (centroid holds the sum of centres until the end) into `into`.
    const auto fold = [this](ObjectInfo& into, const ObjectInfo& from) {
        into.voxel_count += from.voxel_count;
        into.centroid += from.centroid;
        into.bbox_min = into.bbox_min.cwiseMin(from.bbox_min);
        into.bbox_max = into.bbox_max.cwiseMax(from.bbox_max);
        into.height_m = std::max(into.height_m, from.height_m);
    };
    // Whether voxel n (label code `code`) joins the object flooding from voxel v (at c, one
    // step d away) whose highest layer is top_layer.
    const auto mayJoin = [&](int code, std::size_t v, const VoxelIndex& c, const VoxelIndex& n, int dx, int dy, int dz,
                             int top_layer) {
        // A low voxel joins only from the layer above it (NED: dz = +1
        // is one layer deeper), so the object's foot cannot walk
        // along the seabed surface, which also lies in the low band.
        if (code == -2 && cfg_.low_layers_from_above && dz != 1) return false;
        // Diagonally down, only where the map shows the foot widening
        // (low_layers_widen_where_seen): beside a vertical wall the low band
        // is the seabed.
        if (code == -2 && cfg_.low_layers_from_above && cfg_.low_layers_widen_where_seen && (dx != 0 || dy != 0) &&
            !footWidensAt(map, c, n, dx, dy))
            return false;
        // Unconfirmed occupied voxels join only straight down from the
        // object: under its top, where the PS is shadowed.
        if (code == -4 && !(dz == 1 && dx == 0 && dy == 0)) return false;
        // An unobserved voxel in a column the PS swept (-8) joins straight
        // down too, and one step sideways from a voxel no update reached
        // either, unless a surface a sensor saw stands beside it.
        if (code == -8 && (dz != 1 || ((dx != 0 || dy != 0) && (!neverUpdated(map, v) || besideOccupied(map, n)))))
            return false;
        // The voxel the seabed runs through (-6) joins straight down, and
        // one step across from the foot of a face that recedes upward
        // (base_follows_sloped_faces). Only from a voxel above the
        // seabed's own voxel, so the join never walks along the seabed
        // where it steps a layer.
        if (code == -6 && !(dz == 1 && dx == 0 && dy == 0) && !(dz == 1 && recedingFoot(map, c, dx, dy)))
            return false;
        // FLS-only voxels stay within one layer of that top
        // (fls_only_not_above_ps_top): above it, elevation aliases.
        if ((code == -5 || code == -3) && cfg_.fls_only_not_above_ps_top && n.z < top_layer - 1) return false;
        // A voxel the PS crossed joins no higher than that top, and only
        // from its own layer or the one above: were it surface standing
        // above the object, the rays that crossed it would have met it
        // first (a fin over a top edge, where NAV drift shifts the passes).
        if (code == -7 && (n.z < top_layer || n.z < c.z)) return false;
        // FLS-only steps from the PS-confirmed part: at most fls_only_extension.
        if (code == -3 && confirmed_[v] + 1 > cfg_.fls_only_extension) return false;
        return true;
    };
    int next_id = 0;
    for (std::size_t seed = 0; seed < map.size(); ++seed) {
        if (label_[seed] != -1) continue;
        const int id = ++next_id;
        // Seeds are met layer by layer from the top (NED: z index 0 is the
        // shallowest), so the seed is the object's highest PS-confirmed voxel.
        const int top_layer = map.fromLinear(seed).z;
        std::size_t head = 0, tail = 0;
        queue_[tail++] = static_cast<uint32_t>(seed);
        label_[seed] = id;
        join_class_[seed] = 1;
        if (!confirmed_.empty()) confirmed_[seed] = 0;  // from here on: FLS-only steps from the PS-confirmed part
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        VoxelIndex lo{nx_, ny_, nz_}, hi{-1, -1, -1};
        double top_height = 0.0;
        int seabed_joined = 0;  // voxels the seabed runs through: they never make an object big enough
        int joins = 0;          // the earlier object this flood touched (its root id), 0: none
        while (head < tail) {
            const std::size_t v = queue_[head++];
            const VoxelIndex c = map.fromLinear(v);
            sum += map.centreOf(c);
            lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
            hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
            const double top_z = map.origin().z() + c.z * res;
            top_height = std::max(top_height, baseline_[v % layer] - top_z);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const VoxelIndex n{c.x + dx, c.y + dy, c.z + dz};
                        if (!map.contains(n)) continue;
                        const std::size_t nl = map.linear(n);
                        const int taken = label_[nl];  // > 0: an earlier object; kDropped: a group too small
                        if (taken == 0 || taken == id) continue;
                        const bool earlier = taken > 0 || taken == kDropped;
                        if (earlier && !join) continue;
                        const int code = earlier ? -static_cast<int>(join_class_[nl]) : taken;
                        bool may = mayJoin(code, v, c, n, dx, dy, dz, top_layer);
                        // What an earlier flood took is the same object, flooded from
                        // another seed, wherever the two touch above the seabed's own
                        // voxel (there, two objects' feet would meet along the seabed).
                        if (earlier && !may) may = join_class_[nl] != 6 && join_class_[v] != 6;
                        if (!may) continue;
                        if (taken > 0) {  // two earlier objects this flood touches become one too
                            const int r = root(taken);
                            if (joins == 0) {
                                joins = r;
                            } else if (r != joins) {
                                const int keep = std::min(r, joins), gone = std::max(r, joins);
                                fold(objects_[static_cast<std::size_t>(keep - 1)], objects_[static_cast<std::size_t>(gone - 1)]);
                                merged_into_[gone] = keep;
                                joins = keep;
                            }
                            continue;
                        }
                        if (code == -3) confirmed_[nl] = static_cast<uint8_t>(std::min(confirmed_[v] + 1, 255));
                        else if (!confirmed_.empty()) confirmed_[nl] = 0;
                        if (code == -6) ++seabed_joined;
                        join_class_[nl] = static_cast<uint8_t>(-code);
                        label_[nl] = id;
                        queue_[tail++] = static_cast<uint32_t>(nl);
                    }
        }
        const int count = static_cast<int>(tail);
        ObjectInfo o;
        o.voxel_count = count;
        o.centroid = sum;  // the sum until the end
        o.bbox_min = map.origin() + Eigen::Vector3d(lo.x, lo.y, lo.z) * res;
        o.bbox_max = map.origin() + Eigen::Vector3d(hi.x + 1, hi.y + 1, hi.z + 1) * res;
        o.height_m = top_height;
        o.ps_confirmed = require_ps_;  // seeds are PS-confirmed exactly when the variant requires it
        if (joins) {  // part of an earlier object: its voxels take that id
            fold(objects_[static_cast<std::size_t>(joins - 1)], o);
            for (std::size_t q = 0; q < tail; ++q) label_[queue_[q]] = joins;
            --next_id;
            continue;
        }
        const int above_seabed = count - seabed_joined;
        if (above_seabed < cfg_.min_object_voxels || static_cast<int>(objects_.size()) >= cfg_.max_objects) {
            if (above_seabed >= cfg_.min_object_voxels) ++stats_.objects_dropped;
            // Too small: not an object (a later flood may still reach it).
            for (std::size_t q = 0; q < tail; ++q) label_[queue_[q]] = join ? kDropped : 0;
            --next_id;
            continue;
        }
        o.id = id;
        merged_into_[id] = id;
        objects_.push_back(o);
    }
    // Objects that joined another leave the list; the rest are numbered 1..n
    // again, in order. A merge keeps the lower id, so a root precedes the ids
    // that joined it: merged_into_ ends as minus each old id's new number.
    const int floods = static_cast<int>(objects_.size());
    for (int old_id = 1; old_id <= floods; ++old_id) merged_into_[old_id] = root(old_id);
    std::size_t kept = 0;
    for (int old_id = 1; old_id <= floods; ++old_id) {
        if (merged_into_[old_id] != old_id) {
            merged_into_[old_id] = merged_into_[merged_into_[old_id]];
            continue;
        }
        ObjectInfo o = objects_[static_cast<std::size_t>(old_id - 1)];
        o.id = static_cast<int>(kept) + 1;
        o.centroid /= o.voxel_count;
        o.volume_m3 = o.voxel_count * res * res * res;
        objects_[kept++] = o;
        merged_into_[old_id] = -o.id;
    }
    objects_.resize(kept);
    // Low candidates that no seed reached belong to no object.
    for (std::size_t i = 0; i < map.size(); ++i) label_[i] = label_[i] > 0 ? -merged_into_[label_[i]] : 0;
    stats_.objects = static_cast<int>(objects_.size());
}

const SegmentationStats& Segmenter::run(const VoxelMap& map) {
    stats_ = SegmentationStats{};
    objects_.clear();  // keeps capacity: no allocation
    const std::vector<float>& l = map.logOddsData();
    for (std::size_t i = 0; i < l.size(); ++i) {
        occupied_[i] = l[i] > logodds_threshold_ ? 1 : 0;
        stats_.occupied_voxels += occupied_[i];
    }
    std::fill(baseline_.begin(), baseline_.end(), kNaN);
    bool from_echoes = false;
    if (cfg_.seabed_from_ps_echoes) {
        echoSurfaces(map);
        for (double v : surface_) from_echoes = from_echoes || !std::isnan(v);
    }
    if (from_echoes) {
        // Objects stand above the seabed: each pass leaves out the columns the
        // previous one found raised, so the plane settles on the seabed around
        // an object instead of on a blend of both (two passes left the lowest
        // 0.3 m of the 2 m slope boxes below a lifted baseline).
        // The first exclusion is against the lower envelope: a plane through
        // every column tilts onto the top of an object whose seabed was echoed
        // on one side only (a single pass; the seabed behind it in its shadow)
        // and keeps it there through every later pass (survey_field's box:
        // its middle 0.8 m fell below such a baseline).
        // Each fit leaves out what stands out of the residuals' own scatter
        // about the previous one (seabed_raised_sigmas), never more than
        // min_object_height above it.
        double limit = kNoRaiseLimit;
        if (cfg_.seabed_from_lower_envelope) {
            lowerEnvelope(map);
            limit = raisedColumnThreshold(map.resolution());
        }
        fitBaselinePlanes(map, limit);
        for (int pass = 0; pass < 3; ++pass) fitBaselinePlanes(map, raisedColumnThreshold(map.resolution()));
    } else {
        columnSurfaces(map);  // no PS echo (fls_only): the occupied surface
        smoothBaseline(map, kNoRaiseLimit);
        smoothBaseline(map, cfg_.min_object_height);
    }
    baseline_at_echo_centres_ = from_echoes && cfg_.seabed_at_echo_centres;
    // A map saved before PS crossings were counted (SFMAP001/002) holds none
    // anywhere: every crossed voxel would look uncontested.
    crossings_counted_ = false;
    if (cfg_.fls_votes_per_ps_crossing > 0.0 || cfg_.fill_below_not_through_crossed_water)
        for (std::size_t i = 0; i < map.size() && !crossings_counted_; ++i) crossings_counted_ = map.psCrossings(i) > 0;
    // Likewise the FLS's above-seabed votes (none in SFMAP001 maps, none without
    // the FLS): with none anywhere, no voxel's lack of them says anything.
    above_seabed_counted_ = false;
    if (cfg_.fill_below_not_through_crossed_water)
        for (std::size_t i = 0; i < map.size() && !above_seabed_counted_; ++i)
            above_seabed_counted_ = map.flsAboveSeabedVotes(i) > 0;
    if (!confirmed_.empty()) markConfirmed(map);
    label(map);
    return stats_;
}

}  // namespace sonarfusion
