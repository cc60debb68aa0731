// fls.window_changes (issue 14, per-ping FLS geometry): the scenario option that
// changes the FLS range window mid-run, its reader errors, and the frames it makes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim_test_util.hpp"
#include "simulator.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;
using test::TinyScenario;

class WindowChangeTest : public ::testing::Test {
protected:
    void SetUp() override { saveObj(test::flatPlane(20.0), dir.file("plane.obj")); }
    TinyScenario tiny(const std::string& fls_extra) {
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n";
        t.step = 0.0;  // the vehicle holds still: both windows see the same seabed
        t.extra = "fls: {rays_elevation: 64" + fls_extra + "}\n";
        return t;
    }
    std::string errorField(const std::string& fls_extra) {
        try {
            (void)loadScenarioFromString(tiny(fls_extra).yaml(), dir.path());
        } catch (const ScenarioError& e) {
            return e.field();
        }
        ADD_FAILURE() << "loaded: " << fls_extra;
        return "";
    }
    TempDir dir;
};

TEST_F(WindowChangeTest, FramesFromTheChangeOnCarryTheNewWindowAndSeeTheSameSeabed) {
    const Simulator sim(loadScenarioFromString(
        tiny(", window_changes: [{at_sequence: 4, range_min: 0.83, range_max: 7.0}]").yaml(), dir.path()));
    ASSERT_EQ(sim.scenario().fls_sim.window_changes.size(), 1u);
    const SequenceOutput before = sim.simulate(sim.sequences()[0]);
    const SequenceOutput after = sim.simulate(sim.sequences()[4]);
    ASSERT_TRUE(before.has_fls && after.has_fls);
    EXPECT_NEAR(before.fls.row_range.front(), 10.0f, 1e-5);
    EXPECT_NEAR(after.fls.row_range.front(), 7.0f, 1e-5);
    EXPECT_NEAR(after.fls.row_range.back(), 0.83f, 1e-5);
    EXPECT_EQ(after.fls.num_ranges, before.fls.num_ranges);
    EXPECT_EQ(&sim.flsAt(3), &sim.fls());
    EXPECT_NE(&sim.flsAt(4), &sim.fls());
    // The centre beam's seabed echo (noise is off: every non-zero count is
    // echo) spans the same ranges in both windows, within two bins of the 10 m
    // window, at a similar mean level.
    struct Echo {
        double near = 1e9, far = 0.0, level = 0.0;
    };
    auto echo = [](const fls_image_t& m) {
        const int col = m.num_beams / 2;
        Echo e;
        int n = 0;
        for (int r = 0; r < m.num_ranges; ++r) {
            const int v = static_cast<uint8_t>(m.data[static_cast<std::size_t>(r) * m.num_beams + col]);
            if (v == 0) continue;
            e.near = std::min(e.near, static_cast<double>(m.row_range[r]));
            e.far = std::max(e.far, static_cast<double>(m.row_range[r]));
            e.level += v;
            ++n;
        }
        e.level /= std::max(1, n);
        return e;
    };
    const Echo b = echo(before.fls), a = echo(after.fls);
    const double bin = 9.17 / 511;
    EXPECT_NEAR(a.near, b.near, 2.0 * bin);
    EXPECT_NEAR(a.far, b.far, 2.0 * bin);
    EXPECT_GT(b.far - b.near, 0.5);
    EXPECT_GT(b.level, 20.0);
    EXPECT_NEAR(a.level, b.level, 0.2 * b.level);
}

TEST_F(WindowChangeTest, BadEntriesNameTheirField) {
    EXPECT_EQ(errorField(", window_changes: [{at_sequence: 0, range_min: 0.83, range_max: 7}]"),
              "fls.window_changes[0].at_sequence");
    EXPECT_EQ(errorField(", window_changes: [{at_sequence: 4, range_min: 7, range_max: 7}]"),
              "fls.window_changes[0].range_max");
    EXPECT_EQ(errorField(", window_changes: [{at_sequence: 4, range_min: -1, range_max: 7}]"),
              "fls.window_changes[0].range_min");
    EXPECT_EQ(errorField(", window_changes: [{at_sequence: 4, range_max: 7}]"), "fls.window_changes[0].range_min");
    EXPECT_EQ(errorField(", window_changes: [{at_sequence: 4, range_min: 1, range_max: 7, gain: 2}]"),
              "fls.window_changes[0].gain");
    EXPECT_EQ(errorField(", window_changes: [{at_sequence: 4, range_min: 1, range_max: 7}, "
                         "{at_sequence: 4, range_min: 1, range_max: 5}]"),
              "fls.window_changes[1].at_sequence");
    EXPECT_EQ(errorField(", window_changes: 3"), "fls.window_changes");
    EXPECT_EQ(errorField(", rows: 2, row_range: [10, 1], window_changes: [{at_sequence: 4, range_min: 1, range_max: 7}]"),
              "fls.window_changes");
}

TEST_F(WindowChangeTest, TheReferenceWindowChangeScenarioLoads) {
    const Scenario s = loadScenario(std::string(SF_SOURCE_DIR) + "/scenarios/slope_box_90_window_change.yaml");
    ASSERT_EQ(s.fls_sim.window_changes.size(), 1u);
    EXPECT_EQ(s.fls_sim.window_changes[0].at_sequence, 1600);
    EXPECT_DOUBLE_EQ(s.fls_sim.window_changes[0].range_max, 7.0);
}

}  // namespace
}  // namespace sonarfusion::sim
