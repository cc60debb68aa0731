#include "end_face.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <set>

#include "plane_fit.hpp"

namespace sonarfusion::eval {

namespace {
// (depth row, lateral column) of a voxel centre. Centres sit mid-cell, so
// floor() is exact where rounding half-integers would not be.
std::pair<long, long> rowColumn(const GridSpec& grid, const Eigen::Vector3d& c, const Eigen::Vector3d& lat) {
    return {static_cast<long>(std::floor((c.z() - grid.origin.z()) / grid.resolution)),
            static_cast<long>(std::floor((c - grid.origin).dot(lat) / grid.resolution))};
}
}  // namespace

Eigen::Vector3d lateralAxis(const Eigen::Vector3d& outward) { return Eigen::Vector3d(-outward.y(), outward.x(), 0.0); }

std::vector<EndFace> findEndFaces(const TriangleMesh& object, const Eigen::Vector3d& along_track) {
    Eigen::Vector3d axis(along_track.x(), along_track.y(), 0.0);
    axis.normalize();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& v : object.vertices) centre += v;
    centre /= static_cast<double>(object.vertices.size());

    struct Accum {
        Eigen::Vector3d normal = Eigen::Vector3d::Zero(), point = Eigen::Vector3d::Zero();
        double area = 0.0;
        std::vector<Eigen::Vector3d> corners;
    } acc[2];  // [0] front (+axis), [1] back (-axis)
    for (const auto& t : object.triangles) {
        const Eigen::Vector3d &a = object.vertices[t[0]], &b = object.vertices[t[1]], &c = object.vertices[t[2]];
        Eigen::Vector3d n = (b - a).cross(c - a);
        const double area = 0.5 * n.norm();
        if (area <= 0.0) continue;
        n.normalize();
        const Eigen::Vector3d mid = (a + b + c) / 3.0;
        if (n.dot(mid - centre) < 0.0) n = -n;
        if (std::abs(n.dot(axis)) < 0.5) continue;
        Accum& f = acc[n.dot(axis) > 0.0 ? 0 : 1];
        f.normal += area * n;
        f.point += area * mid;
        f.area += area;
        f.corners.insert(f.corners.end(), {a, b, c});
    }
    std::vector<EndFace> faces;
    for (int k = 0; k < 2; ++k) {
        const Accum& f = acc[k];
        if (f.area <= 0.0) continue;
        EndFace face;
        face.outward = k == 0 ? axis : Eigen::Vector3d(-axis);
        face.normal = f.normal.normalized();
        face.point = f.point / f.area;
        face.true_angle_deg = faceAngleDeg(face.normal, face.outward);
        const Eigen::Vector3d lat = lateralAxis(face.outward);
        face.z_top = face.lateral_min = std::numeric_limits<double>::infinity();
        face.z_bottom = face.lateral_max = -std::numeric_limits<double>::infinity();
        for (const auto& p : f.corners) {
            face.z_top = std::min(face.z_top, p.z());
            face.z_bottom = std::max(face.z_bottom, p.z());
            face.lateral_min = std::min(face.lateral_min, p.dot(lat));
            face.lateral_max = std::max(face.lateral_max, p.dot(lat));
        }
        faces.push_back(face);
    }
    return faces;
}

std::vector<Eigen::Vector3d> selectEndFaceVoxels(const GridSpec& grid, const VoxelMask& predicted, const EndFace& face,
                                                 const EndFaceSelection& sel) {
    const double margin = sel.edge_margin * grid.resolution;
    const Eigen::Vector3d lat = lateralAxis(face.outward);
    const double n_dot_t = face.normal.dot(face.outward);
    if (n_dot_t <= 1e-6) return {};
    // (row, column) -> (offset outward from the true plane, voxel centre) of the outermost voxel.
    std::map<std::pair<long, long>, std::pair<double, Eigen::Vector3d>> outermost;
    for (std::size_t i = 0; i < grid.size(); ++i) {
        if (!predicted[i]) continue;
        const Eigen::Vector3d c = grid.centre(i);
        if (c.z() < face.z_top + margin || c.z() > face.z_bottom - margin) continue;
        const double l = c.dot(lat);
        if (l < face.lateral_min + margin || l > face.lateral_max - margin) continue;
        const double offset = face.normal.dot(c - face.point) / n_dot_t;
        if (offset < -sel.inward_window || offset > sel.outward_window) continue;
        const std::pair<long, long> key = rowColumn(grid, c, lat);
        auto it = outermost.find(key);
        if (it == outermost.end() || offset > it->second.first) outermost[key] = {offset, c};
    }
    std::vector<Eigen::Vector3d> points;
    points.reserve(outermost.size());
    for (const auto& kv : outermost) points.push_back(kv.second.second);
    return points;
}

FaceAngle measureEndFace(const GridSpec& grid, const VoxelMask& predicted, const EndFace& face,
                         const EndFaceSelection& sel) {
    FaceAngle out;
    out.true_angle_deg = face.true_angle_deg;
    const std::vector<Eigen::Vector3d> points = selectEndFaceVoxels(grid, predicted, face, sel);
    out.points = points.size();
    std::set<long> rows, columns;
    const Eigen::Vector3d lat = lateralAxis(face.outward);
    for (const auto& p : points) {
        const auto rc = rowColumn(grid, p, lat);
        rows.insert(rc.first);
        columns.insert(rc.second);
    }
    if (rows.size() < 2 || columns.size() < 2) return out;
    if (const auto fit = fitPlane(points)) out.angle_deg = faceAngleDeg(fit->normal, face.outward);
    return out;
}

}  // namespace sonarfusion::eval
