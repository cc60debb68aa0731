// CGAL translation unit: line-of-sight queries on an AABB tree.
#include "visibility.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <cmath>

namespace sonarfusion::eval {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Segment = Kernel::Segment_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point toPoint(const Eigen::Vector3d& v) { return Point(v.x(), v.y(), v.z()); }

// Centroids of the n*n sub-triangles of a regular subdivision: all strictly
// inside the triangle, about `spacing` apart.
void sampleTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double spacing,
                    std::vector<SurfaceSample>& out) {
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
    const Eigen::Vector3d u = (b - a) / n, v = (c - a) / n;
    for (int i = 0; i < n; ++i)
        for (int j = 0; i + j < n; ++j) {
            out.push_back({a + (i + 1.0 / 3.0) * u + (j + 1.0 / 3.0) * v, 0});
            if (i + j < n - 1) out.push_back({a + (i + 2.0 / 3.0) * u + (j + 2.0 / 3.0) * v, 0});
        }
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
    for (const auto& m : targets)
        for (const auto& t : m.triangles)
            sampleTriangle(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], options.sample_spacing, samples);

    for (std::size_t k = 0; k < runs.size() && k < 32; ++k) {
        const SensorRun& run = runs[k];
        const std::vector<SensorPose> poses = thinned(run.poses, options.min_pose_spacing);
        for (SurfaceSample& s : samples) {
            for (const SensorPose& pose : poses) {
                const Eigen::Vector3d ray = s.point - pose.position;
                if (!run.fov.contains(pose.world_from_sensor.transpose() * ray)) continue;
                const double length = ray.norm();
                if (length <= options.self_hit_margin) continue;
                const Eigen::Vector3d end = s.point - ray / length * options.self_hit_margin;
                if (tree.do_intersect(Segment(toPoint(pose.position), toPoint(end)))) continue;
                s.seen_by |= 1u << k;
                break;
            }
        }
    }
    return samples;
}

}  // namespace sonarfusion::eval
