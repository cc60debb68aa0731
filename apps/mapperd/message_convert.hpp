// LCM messages to libfusion's types: one place, for the daemon and the tools.
#pragma once

#include <sonarfusion/nav_state_t.hpp>

#include "sonarfusion/pose.hpp"

namespace sonarfusion {

[[nodiscard]] inline TimedPose timedPoseOf(const nav_state_t& nav) {
    TimedPose p;
    p.utime = nav.utime;
    p.pose.position = Eigen::Vector3d(nav.position_ned[0], nav.position_ned[1], nav.position_ned[2]);
    p.pose.roll = nav.rpy[0];
    p.pose.pitch = nav.rpy[1];
    p.pose.yaw = nav.rpy[2];
    return p;
}

}  // namespace sonarfusion
