// CGAL translation unit: inside test and triangle-box intersection.
#include "voxelise.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace sonarfusion::eval {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Mesh = CGAL::Surface_mesh<Point>;

constexpr double kBoxEpsilon = 1e-6;  // in voxels

Point toPoint(const Eigen::Vector3d& v) { return Point(v.x(), v.y(), v.z()); }

namespace PMP = CGAL::Polygon_mesh_processing;

// The mesh's parts: its connected components, each a Surface_mesh, after
// CGAL's soup repair: identical points merged, faces with a repeated vertex
// dropped, and points duplicated where several parts meet at a vertex or an
// edge (orient_polygon_soup), so closed bars that touch stay closed parts.
std::vector<Mesh> meshParts(const TriangleMesh& in) {
    std::vector<Point> points;
    points.reserve(in.vertices.size());
    for (const auto& v : in.vertices) points.push_back(toPoint(v));
    std::vector<std::array<std::size_t, 3>> faces;
    faces.reserve(in.triangles.size());
    for (const auto& t : in.triangles)
        faces.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2])});
    PMP::merge_duplicate_points_in_polygon_soup(points, faces);
    faces.erase(std::remove_if(faces.begin(), faces.end(),
                               [](const std::array<std::size_t, 3>& f) { return f[0] == f[1] || f[1] == f[2] || f[0] == f[2]; }),
                faces.end());
    PMP::orient_polygon_soup(points, faces);
    Mesh all;
    PMP::polygon_soup_to_polygon_mesh(points, faces, all);
    std::vector<Mesh> parts;
    PMP::split_connected_components(all, parts);
    return parts;
}

// Cell index range [lo, hi] (inclusive, clamped to the grid) covering [a, b].
void cellRange(const GridSpec& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b, Eigen::Vector3i& lo,
               Eigen::Vector3i& hi) {
    const Eigen::Vector3d ca = g.toCell(a), cb = g.toCell(b);
    const Eigen::Vector3i n(g.nx, g.ny, g.nz);
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::max(0, static_cast<int>(std::floor(ca[k] - kBoxEpsilon)));
        hi[k] = std::min(n[k] - 1, static_cast<int>(std::floor(cb[k] + kBoxEpsilon)));
    }
}

CGAL::Bbox_3 cellBox(const GridSpec& g, int x, int y, int z, double grow) {
    const Eigen::Vector3d lo = g.origin + Eigen::Vector3d(x, y, z) * g.resolution - Eigen::Vector3d::Constant(grow);
    const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(g.resolution + 2.0 * grow);
    return CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
}
// [lo, hi) approximated by [lo, hi - eps]: a sheet on a cell boundary claims
// exactly one cell (the one on its max side), as a sheet has no inside.
CGAL::Bbox_3 halfOpenBox(const GridSpec& g, int x, int y, int z, double eps) {
    const Eigen::Vector3d lo = g.origin + Eigen::Vector3d(x, y, z) * g.resolution;
    const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(g.resolution - eps);
    return CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
}
}  // namespace

MeshVoxels voxeliseMesh(const TriangleMesh& mesh, const GridSpec& grid) {
    MeshVoxels out;
    out.solid.assign(grid.size(), 0);
    out.surface.assign(grid.size(), 0);
    VoxelMask inside(grid.size(), 0), crossed(grid.size(), 0), touched(grid.size(), 0);
    const double eps = kBoxEpsilon * grid.resolution;

    // Inside: union over the closed parts, each tested over its own bounding
    // cells (parts may overlap or touch; one parity test over all of them would
    // call an overlap "outside").
    for (const Mesh& part : meshParts(mesh)) {
        if (!CGAL::is_closed(part)) {
            out.closed = false;
            continue;
        }
        const CGAL::Bbox_3 box = PMP::bbox(part);
        Eigen::Vector3i a, b;
        cellRange(grid, Eigen::Vector3d(box.xmin(), box.ymin(), box.zmin()), Eigen::Vector3d(box.xmax(), box.ymax(), box.zmax()),
                  a, b);
        const CGAL::Side_of_triangle_mesh<Mesh, Kernel> side(part);
        for (int z = a.z(); z <= b.z(); ++z)
            for (int y = a.y(); y <= b.y(); ++y)
                for (int x = a.x(); x <= b.x(); ++x) {
                    const std::size_t i = grid.linear(x, y, z);
                    if (!inside[i] && side(toPoint(grid.centre(x, y, z))) != CGAL::ON_UNBOUNDED_SIDE) inside[i] = 1;
                }
    }

    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d& p0 = mesh.vertices[t[0]];
        const Eigen::Vector3d& p1 = mesh.vertices[t[1]];
        const Eigen::Vector3d& p2 = mesh.vertices[t[2]];
        const Triangle tri(toPoint(p0), toPoint(p1), toPoint(p2));
        if (tri.is_degenerate()) continue;
        Eigen::Vector3i a, b;
        cellRange(grid, p0.cwiseMin(p1).cwiseMin(p2), p0.cwiseMax(p1).cwiseMax(p2), a, b);
        for (int z = a.z(); z <= b.z(); ++z)
            for (int y = a.y(); y <= b.y(); ++y)
                for (int x = a.x(); x <= b.x(); ++x) {
                    const std::size_t i = grid.linear(x, y, z);
                    if (crossed[i]) continue;
                    if (!CGAL::do_intersect(tri, cellBox(grid, x, y, z, eps))) continue;
                    touched[i] = 1;
                    if (CGAL::do_intersect(tri, out.closed ? cellBox(grid, x, y, z, -eps) : halfOpenBox(grid, x, y, z, eps)))
                        crossed[i] = 1;
                }
    }

    for (std::size_t i = 0; i < grid.size(); ++i) {
        out.solid[i] = inside[i] || crossed[i];
        out.surface[i] = crossed[i] || (inside[i] && touched[i]);
    }
    return out;
}

MeshVoxels voxeliseMeshes(const std::vector<TriangleMesh>& meshes, const GridSpec& grid) {
    MeshVoxels all;
    all.solid.assign(grid.size(), 0);
    all.surface.assign(grid.size(), 0);
    for (const auto& m : meshes) {
        const MeshVoxels one = voxeliseMesh(m, grid);
        all.closed = all.closed && one.closed;
        for (std::size_t i = 0; i < grid.size(); ++i) {
            all.solid[i] |= one.solid[i];
            all.surface[i] |= one.surface[i];
        }
    }
    return all;
}

}  // namespace sonarfusion::eval

namespace sonarfusion::eval {

int countObjects(const std::vector<TriangleMesh>& meshes) {
    std::vector<Mesh> parts;
    for (const auto& m : meshes)
        for (Mesh& p : meshParts(m)) parts.push_back(std::move(p));
    // Union-find: parts whose surfaces meet (touch or cross), or of which one
    // holds the other, are one object.
    std::vector<std::size_t> parent(parts.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    const auto root = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::vector<CGAL::Bbox_3> boxes;
    for (const Mesh& p : parts) boxes.push_back(PMP::bbox(p));
    for (std::size_t i = 0; i < parts.size(); ++i)
        for (std::size_t j = i + 1; j < parts.size(); ++j) {
            if (root(i) == root(j) || !CGAL::do_overlap(boxes[i], boxes[j])) continue;
            const bool volumes = CGAL::is_closed(parts[i]) && CGAL::is_closed(parts[j]);
            if (PMP::do_intersect(parts[i], parts[j], CGAL::parameters::do_overlap_test_of_bounded_sides(volumes),
                                  CGAL::parameters::do_overlap_test_of_bounded_sides(volumes)))
                parent[root(i)] = root(j);
        }
    int n = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) n += root(i) == i;
    return n;
}

}  // namespace sonarfusion::eval
