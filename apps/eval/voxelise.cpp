// CGAL translation unit: inside test and triangle-box intersection.
#include "voxelise.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>

namespace sonarfusion::eval {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Mesh = CGAL::Surface_mesh<Point>;

constexpr double kBoxEpsilon = 1e-6;  // in voxels

Point toPoint(const Eigen::Vector3d& v) { return Point(v.x(), v.y(), v.z()); }

// Builds a Surface_mesh; returns false when the faces do not form a closed
// 2-manifold (then only the surface cells are used).
bool buildClosedMesh(const TriangleMesh& in, Mesh& out) {
    std::vector<Mesh::Vertex_index> vs;
    vs.reserve(in.vertices.size());
    for (const auto& v : in.vertices) vs.push_back(out.add_vertex(toPoint(v)));
    for (const auto& t : in.triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;
        if (out.add_face(vs[t[0]], vs[t[1]], vs[t[2]]) == Mesh::null_face()) return false;
    }
    return CGAL::is_closed(out);
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

    Mesh sm;
    out.closed = buildClosedMesh(mesh, sm);
    if (out.closed) {
        Eigen::Vector3d lo, hi;
        meshBounds(mesh, lo, hi);
        Eigen::Vector3i a, b;
        cellRange(grid, lo, hi, a, b);
        const CGAL::Side_of_triangle_mesh<Mesh, Kernel> side(sm);
        for (int z = a.z(); z <= b.z(); ++z)
            for (int y = a.y(); y <= b.y(); ++y)
                for (int x = a.x(); x <= b.x(); ++x)
                    if (side(toPoint(grid.centre(x, y, z))) != CGAL::ON_UNBOUNDED_SIDE) inside[grid.linear(x, y, z)] = 1;
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
