// The direction of a sonar ray in the sensor frame (x along the unpitched
// boresight, y starboard, z down): paper Eq. 4 (FLS) and Eq. 11 (PS) without
// the range. One definition for the mapper's sensor models and the
// simulator's rays (docs/design.md, "Frames and conventions").
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace sonarfusion {

// depression: tilt plus elevation (FLS, phi_t1 + phi_k) or plus head angle
// (PS, phi_t2 + phi_p), positive looks down; bearing: positive to starboard.
// Returns (cos d cos b, cos d sin b, sin d), a unit vector.
[[nodiscard]] inline Eigen::Vector3d beamDirection(double depression, double bearing) {
    const double c = std::cos(depression);
    return Eigen::Vector3d(c * std::cos(bearing), c * std::sin(bearing), std::sin(depression));
}

}  // namespace sonarfusion
