#include "sonarfusion/pose.hpp"

#include <cmath>

namespace sonarfusion {

bool Pose::isFinite() const {
    return position.allFinite() && std::isfinite(roll) && std::isfinite(pitch) && std::isfinite(yaw);
}

Eigen::Matrix3d Pose::rotation() const {
    return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

Eigen::Isometry3d sensorToWorld(const Pose& vehicle, const Mounting& mount) {
    Eigen::Isometry3d body_from_sensor = Eigen::Isometry3d::Identity();
    body_from_sensor.linear() = (Eigen::AngleAxisd(mount.yaw, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(mount.roll, Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
    body_from_sensor.translation() = Eigen::Vector3d(mount.x, mount.y, mount.z);
    Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();
    world_from_body.linear() = vehicle.rotation();
    world_from_body.translation() = vehicle.position;
    return world_from_body * body_from_sensor;
}

namespace {
double lerpAngle(double a, double b, double f) {
    double d = std::remainder(b - a, 2.0 * M_PI);  // shortest arc, in [-pi, pi]
    return a + f * d;
}
}  // namespace

Pose interpolate(const TimedPose& a, const TimedPose& b, int64_t utime) {
    if (b.utime == a.utime) return a.pose;
    const double f = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
    Pose p;
    p.position = a.pose.position + f * (b.pose.position - a.pose.position);
    p.roll = lerpAngle(a.pose.roll, b.pose.roll, f);
    p.pitch = lerpAngle(a.pose.pitch, b.pose.pitch, f);
    p.yaw = lerpAngle(a.pose.yaw, b.pose.yaw, f);
    return p;
}

}  // namespace sonarfusion
