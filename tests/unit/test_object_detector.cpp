#include <gtest/gtest.h>

#include <random>

#include "sonarfusion/object_detector.hpp"

using namespace sonarfusion;

TEST(ObjectDetector, FiresOnARisingProfileAndCentresOnIt) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.02);
    int fired_at = -1;
    for (int i = 0; i < 400 && fired_at < 0; ++i) {
        const double x = i * 0.01;
        // Seabed at 20 m; from x = 2.0 m an object 1 m tall.
        const double z = (x >= 2.0 ? 19.0 : 20.0) + noise(rng);
        if (det.addEchoPoint(Eigen::Vector3d(x, 0.0, z))) fired_at = i;
    }
    ASSERT_GE(fired_at, 0);
    EXPECT_EQ(fired_at, 204);  // the fifth risen ping (min_consecutive = 5)
    ASSERT_TRUE(det.detection().has_value());
    EXPECT_NEAR(det.detection()->x(), 2.02, 1e-9);
    EXPECT_NEAR(det.detection()->z(), 19.0, 0.05);
    EXPECT_NEAR(*det.baseline(), 20.0, 0.02);
}

TEST(ObjectDetector, StaysQuietOnFlatNoisySeabedWithSpikes) {
    ObjectDetector det{DetectorConfig{}};
    std::mt19937 rng(2);
    std::normal_distribution<double> noise(0.0, 0.05);
    for (int i = 0; i < 20000; ++i) {
        double z = 20.0 + 0.03 * std::sin(i * 0.01) + noise(rng);
        if (i % 97 == 0) z -= 2.0;  // isolated water-column spikes (fish, speckle)
        ASSERT_FALSE(det.addEchoPoint(Eigen::Vector3d(i * 0.005, 0.0, z))) << "false detection at ping " << i;
    }
    EXPECT_FALSE(det.detected());
}

TEST(ObjectDetector, NeedsABaselineFirstAndIgnoresNonFinite) {
    ObjectDetector det{DetectorConfig{}};
    // An object right at the start: no baseline yet, so no detection.
    for (int i = 0; i < 10; ++i) EXPECT_FALSE(det.addEchoPoint(Eigen::Vector3d(0, 0, 19.0)));
    EXPECT_FALSE(det.addEchoPoint(Eigen::Vector3d(std::nan(""), 0, 19.0)));
    EXPECT_FALSE(det.baseline().has_value());
    det.reset();
    EXPECT_FALSE(det.detected());
}
