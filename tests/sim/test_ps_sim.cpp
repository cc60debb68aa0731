// PS geometry: over a flat seabed the ping peaks at h / sin(tilt + phi_p).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim_test_util.hpp"
#include "simulator.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;
using test::TinyScenario;

int peakBin(const std::vector<uint8_t>& ping) {
    return static_cast<int>(std::max_element(ping.begin(), ping.end()) - ping.begin());
}

class PsSimTest : public ::testing::Test {
protected:
    void SetUp() override { saveObj(test::flatPlane(20.0), dir.file("plane.obj")); }
    Simulator make(const std::string& ps_yaml, int sequences) {
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n";
        t.altitude = altitude;
        t.sequences = sequences;
        t.extra = ps_yaml;
        return Simulator(loadScenarioFromString(t.yaml(), dir.path()));
    }
    const double altitude = 3.0;
    TempDir dir;
};

TEST_F(PsSimTest, PeakAtPredictedRangeForEveryHeadAngle) {
    // A thin vertical beam so the seabed echo falls in one or two bins even
    // at -20 deg, where one degree of depression spans 0.4 m of range.
    const Simulator sim = make("ps: {beam_width_vertical_deg: 0.05}\n", 89);  // one full sector scan
    const double bin = 10.0 / 499;
    for (const SequenceState& q : sim.sequences()) {
        const auto ping = sim.ps().ping(q.pose, q.head_angle, q.index);
        const double predicted = altitude / std::sin(40.0 * kDegToRad + q.head_angle);
        EXPECT_NEAR(sim.ps().rangeOfBin(peakBin(ping)), predicted, bin)
            << "head angle " << q.head_angle / kDegToRad << " deg";
    }
}

TEST_F(PsSimTest, DefaultBeamPeaksInsideItsFootprint) {
    const Simulator sim = make("", 89);
    for (const SequenceState& q : sim.sequences()) {
        const auto ping = sim.ps().ping(q.pose, q.head_angle, q.index);
        const double half = 1.0 * kDegToRad;  // default vertical beam 2 deg
        const double down = 40.0 * kDegToRad + q.head_angle;
        const double r = sim.ps().rangeOfBin(peakBin(ping));
        EXPECT_GE(r, altitude / std::sin(down + half) - 0.02);
        EXPECT_LE(r, altitude / std::sin(down - half) + 0.02);
    }
}

TEST_F(PsSimTest, MessageCarriesGeometryAndHeadAngle) {
    const Simulator sim = make("", 3);
    const SequenceOutput out = sim.simulate(sim.sequences()[2]);
    EXPECT_EQ(out.ps.num_bins, 500);
    EXPECT_EQ(out.ps.intensity.size(), 500u);
    EXPECT_FLOAT_EQ(out.ps.range_min, 0.0f);
    EXPECT_FLOAT_EQ(out.ps.range_max, 10.0f);
    EXPECT_FLOAT_EQ(out.ps.head_angle, static_cast<float>(sim.sequences()[2].head_angle));
    EXPECT_FLOAT_EQ(out.ps.tilt, static_cast<float>(40.0 * kDegToRad));
    EXPECT_EQ(out.ps.utime, out.nav.utime);
    EXPECT_NEAR(out.nav.altitude, altitude, 1e-4);  // altimeter ray straight down
}

}  // namespace
}  // namespace sonarfusion::sim
