// CGAL translation unit: principal component plane fit.
#include "plane_fit.hpp"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/linear_least_squares_fitting_3.h>

#include <cmath>

namespace sonarfusion::eval {

std::optional<PlaneFit> fitPlane(const std::vector<Eigen::Vector3d>& points) {
    using Kernel = CGAL::Simple_cartesian<double>;
    if (points.size() < 3) return std::nullopt;
    std::vector<Kernel::Point_3> pts;
    pts.reserve(points.size());
    for (const auto& p : points) pts.emplace_back(p.x(), p.y(), p.z());
    Kernel::Plane_3 plane;
    Kernel::Point_3 centroid;
    const double quality =
        CGAL::linear_least_squares_fitting_3(pts.begin(), pts.end(), plane, centroid, CGAL::Dimension_tag<0>());
    const Kernel::Vector_3 n = plane.orthogonal_vector();
    PlaneFit fit;
    fit.normal = Eigen::Vector3d(n.x(), n.y(), n.z()).normalized();
    fit.centroid = Eigen::Vector3d(centroid.x(), centroid.y(), centroid.z());
    fit.quality = quality;
    if (!fit.normal.allFinite()) return std::nullopt;
    return fit;
}

double faceAngleDeg(Eigen::Vector3d normal, const Eigen::Vector3d& outward) {
    if (normal.dot(outward) < 0.0) normal = -normal;
    return std::atan2(normal.dot(outward), -normal.z()) * 180.0 / M_PI;
}

}  // namespace sonarfusion::eval
