// Vehicle pose in the NED world frame and the sensor mounting transform.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

struct Pose {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // NED, m
    double roll = 0.0, pitch = 0.0, yaw = 0.0;           // rad, ZYX convention

    // False on NaN/inf anywhere: such a pose must never reach the map.
    [[nodiscard]] bool isFinite() const;
    // world_from_body rotation: R = Rz(yaw) * Ry(pitch) * Rx(roll).
    [[nodiscard]] Eigen::Matrix3d rotation() const;
};

struct TimedPose {
    int64_t utime = 0;
    Pose pose;
};

// world_from_sensor for a sensor mounted on the body. The tilt is not part of
// this transform: Eqs. 4 and 11 apply it inside the sensor model.
[[nodiscard]] Eigen::Isometry3d sensorToWorld(const Pose& vehicle, const Mounting& mount);

// Linear position, shortest-arc angle interpolation between two poses.
[[nodiscard]] Pose interpolate(const TimedPose& a, const TimedPose& b, int64_t utime);

}  // namespace sonarfusion
