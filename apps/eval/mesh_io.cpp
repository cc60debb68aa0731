// CGAL translation unit: mesh file reading only.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>

#include <stdexcept>

#include "mesh.hpp"

namespace sonarfusion::eval {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

TriangleMesh loadMesh(const std::string& path) {
    std::vector<Kernel::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    if (!CGAL::IO::read_polygon_soup(path, points, polygons))
        throw std::runtime_error("mesh " + path + ": cannot read (OFF, OBJ or PLY expected)");
    TriangleMesh mesh;
    mesh.vertices.reserve(points.size());
    for (const auto& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
    for (const auto& poly : polygons) {
        if (poly.size() < 3) throw std::runtime_error("mesh " + path + ": face with fewer than 3 vertices");
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            mesh.triangles.push_back({static_cast<int>(poly[0]), static_cast<int>(poly[k]), static_cast<int>(poly[k + 1])});
    }
    if (mesh.triangles.empty()) throw std::runtime_error("mesh " + path + ": no faces");
    return mesh;
}

void meshBounds(const TriangleMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const auto& v : mesh.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
}

}  // namespace sonarfusion::eval
