// FLS shadows (flsShadowOnSeabed, DetectorConfig::fls_shadow_false_alarm): a
// dark run inside the seabed band that the frame's own speckle statistics make
// rare is a shadow, placed where it starts on the seabed; speckle alone, a far
// band that darkens everywhere, a run with no seabed return before it, or a
// weak seabed return brighter than the water column's noise is not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "sonarfusion/config.hpp"
#include "sonarfusion/fls_detection.hpp"
#include "sonarfusion/fls_model.hpp"
#include "sonarfusion/pose.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {
constexpr double kSeabedDepth = 20.0, kAltitude = 2.5;
constexpr int kNoise = 10;  // pixels at or below it are dark

struct Scene {
    FlsGeometry geometry = MapperConfig{}.fls;
    FlsModel model{geometry};
    Eigen::Isometry3d world_from_sensor = sensorToWorld(test::poseAt(0, 0.0, 0.0, kSeabedDepth - kAltitude).pose,
                                                        Mounting{});
    SeabedFit seabed;
    std::vector<uint8_t> px = std::vector<uint8_t>(static_cast<std::size_t>(geometry.rows) * geometry.beams, 2);
    uint32_t state = 12345;

    Scene() {
        seabed.depth = kSeabedDepth;
        seabed.rms = 0.02;
        for (uint8_t& v : px) v = noise();  // the receiver's noise wherever nothing returns
    }
    uint8_t& at(int row, int col) { return px[static_cast<std::size_t>(row) * geometry.beams + col]; }
    double uniform() {
        state = state * 1664525u + 1013904223u;
        return (state >> 8) / static_cast<double>(1u << 24);
    }
    // Noise alone: 1-5, well under the dark level.
    uint8_t noise() { return static_cast<uint8_t>(1 + 5 * uniform()); }
    // A seabed return that speckle fades under the dark level: 4-10.
    uint8_t fade() { return static_cast<uint8_t>(4 + 7 * uniform()); }
    // Where the beam's arc meets the flat seabed: [near, far] in m.
    std::pair<double, double> seabedRanges(int col) const {
        double lo = 1e9, hi = 0.0;
        for (double e : {model.elevationMin(), model.elevationMax()}) {
            const double rate = (world_from_sensor.linear() * model.directionAt(col, e).cast<double>()).z();
            lo = std::min(lo, kAltitude / rate);
            hi = std::max(hi, kAltitude / rate);
        }
        return {lo, hi};
    }
    // Seabed speckle on every beam: dark with probability p_near over the
    // band's near half and p_far over its far half, bright (60-200) otherwise.
    void speckle(double p_near, double p_far) {
        for (int col = 0; col < geometry.beams; ++col) {
            const auto [near, far] = seabedRanges(col);
            for (int row = 0; row < geometry.rows; ++row) {
                const double r = model.rangeOfRow(row);
                if (r < near || r > far) continue;
                const double p = r < 0.5 * (near + far) ? p_near : p_far;
                at(row, col) = uniform() < p ? fade() : static_cast<uint8_t>(60 + 140 * uniform());
            }
        }
    }
    // Darkens beam col from range r0 for n rows outward to the noise alone
    // (weak: to a seabed return faded under the dark level); returns the first row's range.
    double shadow(int col, double r0, int n, bool weak = false) {
        int first = geometry.rows - 1;
        while (first > 0 && model.rangeOfRow(first) < r0) --first;  // rows run from the far end
        for (int k = 0; k < n && first - k >= 0; ++k) at(first - k, col) = weak ? fade() : noise();
        return model.rangeOfRow(first);
    }
    std::optional<Eigen::Vector3d> detect(double false_alarm = 1e-5, bool like_water = true) const {
        FlsFrame f;
        f.rows = geometry.rows;
        f.cols = geometry.beams;
        f.data = px.data();
        f.data_size = px.size();
        return flsShadowOnSeabed(f, model, world_from_sensor, seabed, 0.1, kNoise, false_alarm, like_water);
    }
};
}  // namespace

TEST(FlsShadow, SpeckleAloneIsNoShadow) {
    Scene s;
    s.speckle(0.08, 0.08);
    EXPECT_FALSE(s.detect().has_value());
}

TEST(FlsShadow, ALongDarkRunBehindASeabedReturnIsAShadowOnTheSeabed) {
    Scene s;
    s.speckle(0.08, 0.08);
    const int col = s.geometry.beams / 2 + 10;
    const auto [near, far] = s.seabedRanges(col);
    const double r0 = s.shadow(col, 0.5 * (near + far), 25);  // about 0.45 m of range
    for (int c : {col - 1, col + 1}) s.shadow(c, 0.5 * (near + far), 20);
    const std::optional<Eigen::Vector3d> p = s.detect();
    ASSERT_TRUE(p.has_value());
    // On the seabed, at the first dark row's range along that beam's bearing.
    EXPECT_NEAR(p->z(), kSeabedDepth, 0.02);
    const Eigen::Vector3d sensor = s.world_from_sensor.translation();
    EXPECT_NEAR((*p - sensor).norm(), r0, 0.03);
    EXPECT_NEAR(std::atan2(p->y() - sensor.y(), p->x() - sensor.x()), s.model.bearingOfColumn(col), 0.01);
    // A false-alarm rate far below what the run scores: not a shadow at that rate.
    EXPECT_FALSE(s.detect(1e-30).has_value());
}

TEST(FlsShadow, ARunIntoTheBandsFarEndCounts) {
    Scene s;
    s.speckle(0.08, 0.08);
    const int col = 20;
    const auto [near, far] = s.seabedRanges(col);
    s.shadow(col, far - 0.6, 60);  // from 0.6 m before the seabed's far end to beyond it
    EXPECT_TRUE(s.detect().has_value());
}

TEST(FlsShadow, ARunWithNoSeabedReturnBeforeItIsNot) {
    Scene s;
    s.speckle(0.08, 0.08);
    const int col = 30;
    const auto [near, far] = s.seabedRanges(col);
    s.shadow(col, near - 0.3, 50);  // from the water before the band well into it
    EXPECT_FALSE(s.detect().has_value());
}

// The seabed's returns weaken toward the band's far end (a seabed falling
// away): there dark runs of a dozen rows are ordinary, and judged by the far
// part's own statistics they are no shadow; judged by the whole band's they
// would be.
TEST(FlsShadow, TheFarEndsOwnDarknessIsNoShadow) {
    Scene s;
    s.speckle(0.03, 0.55);
    EXPECT_FALSE(s.detect().has_value());
    // A shadow in the near half still is one.
    const int col = 50;
    const auto [near, far] = s.seabedRanges(col);
    s.shadow(col, near + 0.25 * (far - near), 25);
    EXPECT_TRUE(s.detect().has_value());
}

// DetectorConfig::fls_shadow_like_water: a seabed turned away from the sonar
// (a swell's lee) returns weakly, under the dark level for as many rows as a
// shadow, but brighter than the water column's noise. Darkness alone calls it
// a shadow; its level says it is none. A shadow beside it still is one.
TEST(FlsShadow, AWeakSeabedIsNoShadow) {
    Scene s;
    s.speckle(0.08, 0.08);
    for (int col = 80; col < 84; ++col) {
        const auto [near, far] = s.seabedRanges(col);
        s.shadow(col, 0.5 * (near + far), 30, /*weak=*/true);
    }
    EXPECT_TRUE(s.detect(1e-5, /*like_water=*/false).has_value());
    EXPECT_FALSE(s.detect(1e-5, /*like_water=*/true).has_value());
    const int col = 40;
    const auto [near, far] = s.seabedRanges(col);
    const double r0 = s.shadow(col, 0.5 * (near + far), 25);
    const std::optional<Eigen::Vector3d> p = s.detect(1e-5, /*like_water=*/true);
    ASSERT_TRUE(p.has_value());
    EXPECT_NEAR((*p - s.world_from_sensor.translation()).norm(), r0, 0.03);
}

TEST(FlsShadow, NothingWithoutASeabedBelowTheSensor) {
    Scene s;
    s.speckle(0.08, 0.08);
    s.shadow(40, 0.5 * (s.seabedRanges(40).first + s.seabedRanges(40).second), 30);
    s.seabed.depth = kSeabedDepth - kAltitude - 0.05;  // the plane at (or above) the sensor less the margin
    EXPECT_FALSE(s.detect().has_value());
    EXPECT_FALSE(s.detect(0.0).has_value());  // 0: no shadow evidence
}
