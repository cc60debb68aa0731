#include <gtest/gtest.h>

#include "sonarfusion/nav_buffer.hpp"
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

TEST(NavBuffer, BracketsExactAndInterpolatesAndRefusesGaps) {
    NavBuffer nav(8, 1000);
    ASSERT_EQ(nav.add(test::poseAt(1000, 0, 0, 0)), NavBuffer::AddResult::Ok);
    ASSERT_EQ(nav.add(test::poseAt(2000, 1, 0, 0)), NavBuffer::AddResult::Ok);
    ASSERT_EQ(nav.add(test::poseAt(5000, 4, 0, 0)), NavBuffer::AddResult::Ok);
    Pose out;
    EXPECT_EQ(nav.poseAt(2000, out), PoseLookup::Ok);
    EXPECT_DOUBLE_EQ(out.position.x(), 1.0);
    EXPECT_EQ(nav.poseAt(1250, out), PoseLookup::Ok);
    EXPECT_DOUBLE_EQ(out.position.x(), 0.25);
    EXPECT_EQ(nav.poseAt(3000, out), PoseLookup::GapTooLarge);  // 3 ms gap > 1 ms
    EXPECT_EQ(nav.poseAt(999, out), PoseLookup::NoBracket);     // no extrapolation
    EXPECT_EQ(nav.poseAt(5001, out), PoseLookup::NoBracket);
}

TEST(NavBuffer, RingKeepsNewestAndRejectsDisorder) {
    NavBuffer nav(3, 1000000);
    for (int i = 1; i <= 5; ++i) ASSERT_EQ(nav.add(test::poseAt(i * 10, i, 0, 0)), NavBuffer::AddResult::Ok);
    EXPECT_EQ(nav.size(), 3);
    Pose out;
    EXPECT_EQ(nav.poseAt(20, out), PoseLookup::NoBracket);  // overwritten
    EXPECT_EQ(nav.poseAt(35, out), PoseLookup::Ok);
    EXPECT_DOUBLE_EQ(out.position.x(), 3.5);
    EXPECT_EQ(nav.add(test::poseAt(50, 0, 0, 0)), NavBuffer::AddResult::OutOfOrder);
    TimedPose bad = test::poseAt(60, 0, 0, 0);
    bad.pose.roll = std::numeric_limits<double>::infinity();
    EXPECT_EQ(nav.add(bad), NavBuffer::AddResult::NonFinite);
}

TEST(NavBuffer, ExtremeTimeStampsNeverOverflowIntoAFalseBracket) {
    // Time stamps come off the network; their difference must not wrap.
    NavBuffer nav(8, 1000);
    ASSERT_EQ(nav.add(test::poseAt(INT64_MIN + 5, 0, 0, 0)), NavBuffer::AddResult::Ok);
    ASSERT_EQ(nav.add(test::poseAt(INT64_MAX - 5, 1, 0, 0)), NavBuffer::AddResult::Ok);
    Pose out;
    EXPECT_EQ(nav.poseAt(0, out), PoseLookup::GapTooLarge);
}
