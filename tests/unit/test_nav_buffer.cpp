// NavBuffer (nav_buffer.hpp): the NAV ring the daemon interpolates poses from.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "sonarfusion/nav_buffer.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

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
