#include <gtest/gtest.h>

#include "sonarfusion/pose.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

TEST(Pose, YawNinetyTurnsForwardToEast) {
    Pose p;
    p.yaw = M_PI / 2;
    const Eigen::Vector3d fwd = p.rotation() * Eigen::Vector3d::UnitX();
    EXPECT_TRUE(fwd.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(Pose, PositivePitchIsNoseUp) {
    Pose p;
    p.pitch = 0.3;
    const Eigen::Vector3d fwd = p.rotation() * Eigen::Vector3d::UnitX();
    EXPECT_LT(fwd.z(), 0.0);  // NED: up is -z
}

TEST(Pose, SensorToWorldAppliesMountingThenVehicle) {
    Pose p;
    p.position = Eigen::Vector3d(1, 2, 3);
    p.yaw = M_PI;  // heading south
    Mounting m;
    m.x = 0.5;  // half a metre forward on the body
    const Eigen::Vector3d s = sensorToWorld(p, m).translation();
    EXPECT_TRUE(s.isApprox(Eigen::Vector3d(0.5, 2, 3), 1e-12));
}

TEST(Pose, InterpolatesShortestArcAcrossPi) {
    TimedPose a = test::poseAt(0, 0, 0, 0, M_PI - 0.1);
    TimedPose b = test::poseAt(100, 10, 0, 0, -M_PI + 0.1);
    const Pose mid = interpolate(a, b, 50);
    EXPECT_NEAR(mid.position.x(), 5.0, 1e-12);
    EXPECT_NEAR(std::cos(mid.yaw), -1.0, 1e-9);  // through pi, not through 0
}
