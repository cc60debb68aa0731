// Least-squares plane through points (CGAL::linear_least_squares_fitting_3,
// orthogonal regression), and the angle of a face from the horizontal.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace sonarfusion::eval {

struct PlaneFit {
    Eigen::Vector3d normal;    // unit
    Eigen::Vector3d centroid;
    double quality = 0.0;      // CGAL's fitting quality: 1 = perfect plane, 0 = isotropic cloud
};

// Empty when fewer than 3 points.
[[nodiscard]] std::optional<PlaneFit> fitPlane(const std::vector<Eigen::Vector3d>& points);

// Angle (deg) of a face from the horizontal, measured inside the object, for
// a face whose outside lies along the horizontal unit vector `outward` (NED,
// z down): atan2(n.outward, -n.z) with n oriented so that n.outward >= 0.
// 90 = vertical wall, < 90 leans out (a slope), > 90 overhangs.
[[nodiscard]] double faceAngleDeg(Eigen::Vector3d normal, const Eigen::Vector3d& outward);

}  // namespace sonarfusion::eval
