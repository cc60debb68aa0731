// CGAL translation unit: line-of-sight queries on an AABB tree.
#include "visibility.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

namespace sonarfusion::eval {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Segment = Kernel::Segment_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point toPoint(const Eigen::Vector3d& v) { return Point(v.x(), v.y(), v.z()); }

// Samples about `spacing` apart, all strictly inside the triangle.
//  - Normally the centroids of the n*n sub-triangles of a regular subdivision,
//    n = ceil(longest edge / spacing).
//  - A sliver (long and thin) would get n*n samples on a tiny area: when that
//    is more than kMaxOversampling times the count of spacing-sided equilateral
//    triangles its area holds, it is sampled in rows instead: rows parallel to
//    its longest edge, `spacing` apart across it, points `spacing` apart along
//    each row (cell centres), so the count follows the area.
constexpr double kMaxOversampling = 4.0;

// Indices k in [0, count) whose points base + (k + offset) * step lie in
// `box`, widened by one index each side (the caller tests each point itself):
// a row of samples crossing the box's edge costs only the part inside it.
void rowInBox(const Eigen::Vector3d& base, const Eigen::Vector3d& step, double offset, int count,
              const Eigen::AlignedBox3d& box, int& first, int& last) {
    double lo = -1e300, hi = 1e300;
    for (int a = 0; a < 3; ++a) {
        if (step[a] == 0.0) {
            if (base[a] < box.min()[a] || base[a] > box.max()[a]) lo = 1.0, hi = 0.0;
            continue;
        }
        const double t0 = (box.min()[a] - base[a]) / step[a] - offset, t1 = (box.max()[a] - base[a]) / step[a] - offset;
        lo = std::max(lo, std::min(t0, t1));
        hi = std::min(hi, std::max(t0, t1));
    }
    if (!(lo <= hi)) {
        first = 0, last = -1;
        return;
    }
    first = static_cast<int>(std::max(0.0, std::floor(lo) - 1.0));
    last = static_cast<int>(std::min(static_cast<double>(count - 1), std::ceil(hi) + 1.0));
}

// `reach`: samples outside it are not made (no pose is within range of them).
// A triangle wholly inside is sampled as it always was, sample for sample.
void sampleTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double spacing,
                    const Eigen::AlignedBox3d& reach, std::vector<SurfaceSample>& out) {
    Eigen::AlignedBox3d bounds(a);
    bounds.extend(b).extend(c);
    if (!reach.intersects(bounds)) return;
    const bool clipped = !reach.contains(bounds);
    const auto keep = [&](const Eigen::Vector3d& p) {
        if (!clipped || reach.contains(p)) out.push_back({p, 0});
    };
    const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
    const double longest = std::max({ab, bc, ca});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const double equilateral = std::sqrt(3.0) / 4.0 * spacing * spacing;
    if (static_cast<double>(n) * n <= kMaxOversampling * std::max(1.0, area / equilateral)) {
        const Eigen::Vector3d u = (b - a) / n, v = (c - a) / n;
        for (int i = 0; i < n; ++i) {
            int first = 0, last = n - i - 1;
            if (clipped) {  // the row's two kinds of sample, each on its own line
                int first2 = 0, last2 = -1;
                rowInBox(a + (i + 1.0 / 3.0) * u, v, 1.0 / 3.0, n - i, reach, first, last);
                rowInBox(a + (i + 2.0 / 3.0) * u, v, 2.0 / 3.0, n - i, reach, first2, last2);
                if (first2 <= last2) {
                    first = first <= last ? std::min(first, first2) : first2;
                    last = std::max(last, last2);
                }
            }
            for (int j = first; j <= last; ++j) {
                keep(a + (i + 1.0 / 3.0) * u + (j + 1.0 / 3.0) * v);
                if (i + j < n - 1) keep(a + (i + 2.0 / 3.0) * u + (j + 2.0 / 3.0) * v);
            }
        }
        return;
    }
    // Sliver: p, q = the longest edge, r = the opposite vertex.
    const Eigen::Vector3d *p = &a, *q = &b, *r = &c;
    if (bc == longest) p = &b, q = &c, r = &a;
    else if (ca == longest) p = &c, q = &a, r = &b;
    const double height = 2.0 * area / longest;
    const int rows = std::max(1, static_cast<int>(std::ceil(height / spacing)));
    for (int j = 0; j < rows; ++j) {
        const double t = (j + 0.5) / rows;  // 0 on the longest edge, 1 at r
        const Eigen::Vector3d from = *p + t * (*r - *p), to = *q + t * (*r - *q);
        const int m = std::max(1, static_cast<int>(std::ceil((1.0 - t) * longest / spacing)));
        int first = 0, last = m - 1;
        if (clipped) rowInBox(from, (to - from) / m, 0.5, m, reach, first, last);
        for (int k = first; k <= last; ++k) keep(from + (k + 0.5) / m * (to - from));
    }
}

// Where any run's sensor could see: the box around all its poses, widened by
// its largest range. A surface sample outside it is out of range of every
// pose, so it is never seen; not making it keeps a mesh far larger than the
// survey (a wreck or pipeline seen in part, a mesh in millimetres left
// unscaled) from needing its whole surface sampled.
// With no pose at all nothing is seen; the whole surface is sampled then.
Eigen::AlignedBox3d reachOf(const std::vector<SensorRun>& runs) {
    Eigen::AlignedBox3d box;  // empty
    for (const SensorRun& run : runs)
        for (const SensorPose& pose : run.poses) {
            const Eigen::Vector3d r = Eigen::Vector3d::Constant(std::max(0.0, run.fov.range_max));
            box.extend(pose.position - r).extend(pose.position + r);
        }
    if (box.isEmpty()) {
        const double inf = std::numeric_limits<double>::infinity();
        return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
    }
    return box;
}

std::vector<SensorPose> thinned(const std::vector<SensorPose>& poses, double spacing) {
    std::vector<SensorPose> kept;
    for (const auto& p : poses) {
        if (!kept.empty()) {
            const SensorPose& last = kept.back();
            const double turn = Eigen::AngleAxisd(last.world_from_sensor.transpose() * p.world_from_sensor).angle();
            if ((p.position - last.position).norm() < spacing && turn < 1.0 * M_PI / 180.0) continue;
        }
        kept.push_back(p);
    }
    return kept;
}
}  // namespace

SensorFov SensorFov::fls(const FlsGeometry& g) {
    return {-0.5 * g.fov_horizontal, 0.5 * g.fov_horizontal, g.tilt + g.elevation_min, g.tilt + g.elevation_max,
            g.range_min, g.range_max};
}

SensorFov SensorFov::ps(const PsGeometry& g) {
    return {g.fan_min, g.fan_max, g.tilt + g.head_min, g.tilt + g.head_max, g.range_min, g.range_max};
}

bool SensorFov::contains(const Eigen::Vector3d& p) const {
    const double range = p.norm();
    if (range < range_min || range > range_max) return false;
    const double bearing = std::atan2(p.y(), p.x());
    if (bearing < bearing_min || bearing > bearing_max) return false;
    const double elevation = std::atan2(p.z(), std::hypot(p.x(), p.y()));
    return elevation >= elevation_min && elevation <= elevation_max;
}

namespace {

// A cheap, conservative pre-test of SensorFov::contains (never rejects a point
// contains() accepts: every bound is widened by kSlack), so the exact test with
// its atan2 calls runs only on the few candidates that pass.
class FovPrefilter {
public:
    explicit FovPrefilter(const SensorFov& f) {
        r2_min_ = f.range_min > 0 ? f.range_min * f.range_min * (1.0 - kSlack) : -1.0;
        r2_max_ = f.range_max * f.range_max * (1.0 + kSlack);
        bearing_ = f.bearing_max - f.bearing_min < M_PI - 2.0 * kSlack;
        if (bearing_) {
            lo_ = {std::cos(f.bearing_min - kSlack), std::sin(f.bearing_min - kSlack)};
            hi_ = {std::cos(f.bearing_max + kSlack), std::sin(f.bearing_max + kSlack)};
        }
        const double e_lo = f.elevation_min - kSlack, e_hi = f.elevation_max + kSlack;
        elevation_lo_ = e_lo > -M_PI / 2 + kSlack;
        elevation_hi_ = e_hi < M_PI / 2 - kSlack;
        if (elevation_lo_) tan_lo_ = std::tan(e_lo);
        if (elevation_hi_) tan_hi_ = std::tan(e_hi);
    }
    [[nodiscard]] bool mayContain(const Eigen::Vector3d& p) const {
        const double r2 = p.squaredNorm();
        if (r2 > r2_max_ || r2 < r2_min_) return false;
        if (bearing_) {
            // bearing in [lo, hi] (span < pi): p is left of lo's ray and right of hi's
            if (lo_.x() * p.y() - lo_.y() * p.x() < 0.0) return false;
            if (p.x() * hi_.y() - p.y() * hi_.x() < 0.0) return false;
        }
        const double h = std::sqrt(p.x() * p.x() + p.y() * p.y());
        if (elevation_lo_ && p.z() < h * tan_lo_ - kSlack * (h + std::abs(p.z()))) return false;
        if (elevation_hi_ && p.z() > h * tan_hi_ + kSlack * (h + std::abs(p.z()))) return false;
        return true;
    }

private:
    static constexpr double kSlack = 1e-6;  // rad, and relative
    double r2_min_ = 0, r2_max_ = 0;
    bool bearing_ = false, elevation_lo_ = false, elevation_hi_ = false;
    Eigen::Vector2d lo_ = Eigen::Vector2d::Zero(), hi_ = Eigen::Vector2d::Zero();
    double tan_lo_ = 0, tan_hi_ = 0;
};

struct PreparedRun {
    const SensorRun* run = nullptr;
    FovPrefilter prefilter;
    std::vector<SensorPose> poses;  // thinned
};

// Line of sight with a few exact shortcuts, all with the same CGAL predicate
// (Kernel::do_intersect of a Segment_3 and a Triangle_3) the AABB tree uses,
// so the answer is exactly tree.do_intersect's:
//  - the triangles that blocked the last sight lines are tried first
//    (neighbouring samples and poses are mostly blocked by the same face);
//  - otherwise the tree is asked for any blocking triangle, which is remembered.
class SightTester {
public:
    SightTester(const Tree& tree, const std::vector<Triangle>& triangles) : tree_(tree), triangles_(triangles) {}

    [[nodiscard]] bool blocked(const Segment& s) {
        for (std::size_t k = 0; k < kCache; ++k) {
            const std::size_t id = cache_[k];
            if (id != kNone && CGAL::do_intersect(s, triangles_[id])) return true;
        }
        const auto hit = tree_.any_intersected_primitive(s);
        if (!hit) return false;
        cache_[next_] = static_cast<std::size_t>(*hit - triangles_.begin());
        next_ = (next_ + 1) % kCache;
        return true;
    }

private:
    static constexpr std::size_t kCache = 4;
    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    const Tree& tree_;
    const std::vector<Triangle>& triangles_;
    std::size_t cache_[kCache] = {kNone, kNone, kNone, kNone};
    std::size_t next_ = 0;
};

// Sets bit k of every sample in [begin, end) that run k sees.
void testSamples(std::vector<SurfaceSample>& samples, std::size_t begin, std::size_t end,
                 const std::vector<PreparedRun>& runs, SightTester& sight, const VisibilityOptions& options) {
    for (std::size_t k = 0; k < runs.size(); ++k) {
        const PreparedRun& pr = runs[k];
        const std::size_t n = pr.poses.size();
        std::size_t start = 0;  // the pose that saw the previous sample: try it first
        for (std::size_t i = begin; i < end; ++i) {
            SurfaceSample& s = samples[i];
            for (std::size_t step = 0; step < n; ++step) {
                const std::size_t j = (start + step) % n;
                const SensorPose& pose = pr.poses[j];
                const Eigen::Vector3d ray = s.point - pose.position;
                const Eigen::Vector3d in_sensor = pose.world_from_sensor.transpose() * ray;
                if (!pr.prefilter.mayContain(in_sensor) || !pr.run->fov.contains(in_sensor)) continue;
                const double length = ray.norm();
                if (length <= options.self_hit_margin) continue;
                const Eigen::Vector3d end_point = s.point - ray / length * options.self_hit_margin;
                if (sight.blocked(Segment(toPoint(pose.position), toPoint(end_point)))) continue;
                s.seen_by |= 1u << k;
                start = j;
                break;
            }
        }
    }
}

}  // namespace

std::vector<SurfaceSample> sampleVisibleSurface(const std::vector<TriangleMesh>& targets,
                                                const std::vector<TriangleMesh>& occluders,
                                                const std::vector<SensorRun>& runs, const VisibilityOptions& options) {
    std::vector<Triangle> triangles;
    for (const auto& m : occluders)
        for (const auto& t : m.triangles) {
            const Triangle tri(toPoint(m.vertices[t[0]]), toPoint(m.vertices[t[1]]), toPoint(m.vertices[t[2]]));
            if (!tri.is_degenerate()) triangles.push_back(tri);
        }
    Tree tree(triangles.begin(), triangles.end());
    tree.build();

    std::vector<SurfaceSample> samples;
    const Eigen::AlignedBox3d reach = reachOf(runs);
    for (const auto& m : targets)
        for (const auto& t : m.triangles)
            sampleTriangle(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], options.sample_spacing, reach,
                           samples);

    std::vector<PreparedRun> prepared;
    for (std::size_t k = 0; k < runs.size() && k < 32; ++k)
        prepared.push_back({&runs[k], FovPrefilter(runs[k].fov), thinned(runs[k].poses, options.min_pose_spacing)});

    // Samples are independent: blocks of them go to the threads in turn. Each
    // sample's bits depend on nothing but the sample, so the result does not
    // depend on the thread count or the schedule.
    constexpr std::size_t kBlock = 512;
    const std::size_t blocks = (samples.size() + kBlock - 1) / kBlock;
    const std::size_t threads =
        std::min(static_cast<std::size_t>(std::max(1, options.threads)), std::max<std::size_t>(1, blocks));
    std::atomic<std::size_t> next_block{0};
    auto worker = [&]() {
        SightTester sight(tree, triangles);
        for (std::size_t b = next_block++; b < blocks; b = next_block++)
            testSamples(samples, b * kBlock, std::min(samples.size(), (b + 1) * kBlock), prepared, sight, options);
    };
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    return samples;
}

}  // namespace sonarfusion::eval
