// A local seabed plane fitted to PS seabed echoes (the detector's, paper 2.1),
// shared by the detector and the FLS update (votes the seabed cannot explain).
#pragma once

#include <Eigen/Core>

namespace sonarfusion {

// The local seabed a detector sees: a plane z = z0 + g . (xy - xy0) and the
// rms scatter of the echoes about it.
struct SeabedFit {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // xy0, the mean of the fitted echoes
    double depth = 0.0;                                // z0 (NED, m)
    Eigen::Vector2d gradient = Eigen::Vector2d::Zero(); // dz/dx, dz/dy
    double rms = 0.0;                                  // m, robust residual scatter (1.4826 x MAD)
    int echoes = 0;
    [[nodiscard]] double depthAt(const Eigen::Vector2d& xy) const { return depth + gradient.dot(xy - centre); }
    // How fast a ray along direction d (NED) closes on the plane per unit of
    // length: its descent less the plane's along its heading. A ray from above
    // meets the plane, at (depth under it) / this, only when this is positive.
    template <class Vec3>
    [[nodiscard]] double closingRate(const Vec3& d) const {
        return d.z() - gradient.x() * d.x() - gradient.y() * d.y();
    }
};

}  // namespace sonarfusion
