// Scenario loading: the reference files, defaults, and errors that name the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scenario.hpp"
#include "sim_test_util.hpp"
#include "trajectory.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;
using test::TinyScenario;

class ScenarioTest : public ::testing::Test {
protected:
    void SetUp() override { saveObj(test::flatPlane(20.0), dir.file("plane.obj")); }
    Scenario load(const std::string& yaml) { return loadScenarioFromString(yaml, dir.path()); }
    // The field named by the error of loading `yaml` (fails the test if it loads).
    std::string errorField(const std::string& yaml) {
        try {
            (void)load(yaml);
        } catch (const ScenarioError& e) {
            EXPECT_NE(std::string(e.what()).find(e.field()), std::string::npos) << e.what();
            return e.field();
        }
        ADD_FAILURE() << "scenario loaded although it is bad:\n" << yaml;
        return "";
    }
    TinyScenario tiny() {
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n";
        return t;
    }
    TempDir dir;
};

TEST_F(ScenarioTest, ReferenceScenariosLoadWithPaperParameters) {
    for (int alpha : {90, 60}) {
        const Scenario s = loadScenario(std::string(SF_SOURCE_DIR) + "/scenarios/slope_box_" +
                                        std::to_string(alpha) + ".yaml");
        EXPECT_DOUBLE_EQ(s.trueFaceAngleDeg(), alpha);
        const auto count = [&](MeshRole role) {
            return std::count_if(s.scene.meshes.begin(), s.scene.meshes.end(),
                                 [&](const MeshSpec& m) { return m.role == role; });
        };
        ASSERT_EQ(count(MeshRole::Object), 1);
        ASSERT_EQ(count(MeshRole::Seabed), 1);
        EXPECT_EQ(s.fls.beams, 96);
        EXPECT_EQ(s.fls.rows, 512);
        EXPECT_NEAR(s.fls.tilt, 40.0 * kDegToRad, 1e-12);
        EXPECT_EQ(s.ps.bins, 500);
        const auto seqs = buildSequences(s);
        ASSERT_EQ(seqs.size(), 3200u);
        int fls = 0;
        for (const auto& q : seqs) fls += q.has_fls;
        EXPECT_EQ(fls, 800);
        // Pass 1 heads north from 6 m before the box, pass 2 south.
        EXPECT_NEAR(seqs[0].pose.position.x(), -6.0, 1e-9);
        EXPECT_NEAR(seqs[0].pose.position.z(), 20.0 - 3.12, 1e-9);
        EXPECT_NEAR(seqs[1599].pose.position.x(), -6.0 + 1599 * 0.005, 1e-9);
        EXPECT_NEAR(seqs[1600].pose.position.x(), 6.0, 1e-9);
        EXPECT_NEAR(seqs[1600].pose.yaw, M_PI, 1e-9);
    }
}

TEST_F(ScenarioTest, SequencesHaveIncreasingTimesAndSectorScan) {
    TinyScenario t = tiny();
    t.sequences = 200;
    const Scenario s = load(t.yaml());
    const auto seqs = buildSequences(s);
    ASSERT_EQ(seqs.size(), 200u);
    for (std::size_t i = 1; i < seqs.size(); ++i) {
        EXPECT_EQ(seqs[i].utime - seqs[i - 1].utime, 50000);  // 50 ms default period
        EXPECT_EQ(seqs[i].has_fls, i % 4 == 0);
        // The sector is split into whole steps: 40 deg / round(40 / 0.9) = 0.909 deg.
        EXPECT_NEAR(std::fabs(seqs[i].head_angle - seqs[i - 1].head_angle), 40.0 * kDegToRad / 44, 1e-9);
        EXPECT_GE(seqs[i].head_angle, s.ps.head_min - 1e-12);
        EXPECT_LE(seqs[i].head_angle, s.ps.head_max + 1e-12);
    }
    EXPECT_DOUBLE_EQ(seqs[0].head_angle, s.ps.head_min);
    EXPECT_NEAR(seqs[44].head_angle, s.ps.head_max, 1e-12);  // 40 deg / 0.9 deg -> 44 steps
    EXPECT_NEAR(seqs[88].head_angle, s.ps.head_min, 1e-12);
}

TEST_F(ScenarioTest, WaypointsFollowThePolyline) {
    const std::string yaml =
        "scene: {meshes: [{file: plane.obj, role: seabed}]}\n"
        "trajectory:\n  waypoints:\n    - {step: 0.5, points: [[0, 0, 17], [2, 0, 17], [2, 2, 17]]}\n";
    const auto seqs = buildSequences(load(yaml));
    ASSERT_EQ(seqs.size(), 8u);  // 4 per 2 m segment at 0.5 m
    EXPECT_NEAR(seqs[3].pose.position.x(), 1.5, 1e-12);
    EXPECT_NEAR(seqs[4].pose.position.x(), 2.0, 1e-12);
    EXPECT_NEAR(seqs[5].pose.position.y(), 0.5, 1e-12);
    EXPECT_NEAR(seqs[5].pose.yaw, M_PI / 2, 1e-12);
}

TEST_F(ScenarioTest, MissingMeshNamesTheField) {
    TinyScenario t = tiny();
    t.meshes = "- {file: plane.obj, role: seabed}\n- {file: nowhere.obj, role: object}\n";
    EXPECT_EQ(errorField(t.yaml()), "scene.meshes[1].file");
}

// A mesh from another project goes where the scenario says: scale (file
// units to metres), then rpy_deg as a vehicle's attitude (Z-Y-X), then position.
TEST_F(ScenarioTest, MeshPlacementIsReadAndChecked) {
    TinyScenario t = tiny();
    t.meshes = "- {file: plane.obj, role: seabed}\n"
               "- {file: plane.obj, role: object, scale: 0.001, position: [1, -2, 19.5], rpy_deg: [180, 0, 90]}\n";
    const Scenario s = load(t.yaml());
    ASSERT_EQ(s.scene.meshes.size(), 2u);
    const MeshSpec& bed = s.scene.meshes[0];
    EXPECT_EQ(bed.scale, 1.0);
    EXPECT_TRUE(bed.pose().matrix() == Eigen::Matrix4d::Identity());  // the defaults leave the file as it is
    const MeshSpec& m = s.scene.meshes[1];
    EXPECT_DOUBLE_EQ(m.scale, 0.001);
    const Eigen::Isometry3d pose = m.pose();
    EXPECT_LT((pose.translation() - Eigen::Vector3d(1, -2, 19.5)).norm(), 1e-12);
    // Roll 180 deg (a z-up file upside down in NED, z down), then yaw 90 deg.
    EXPECT_LT((pose.linear() * Eigen::Vector3d::UnitZ() + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    EXPECT_LT((pose.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
    EXPECT_LT((pose.linear() * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitX()).norm(), 1e-12);

    const std::string bad_cases[][2] = {
        {"scale: 0", "scene.meshes[0].scale"},
        {"scale: -1", "scene.meshes[0].scale"},
        {"position: [1, 2]", "scene.meshes[0].position"},
        {"rpy_deg: [0, 0, 0, 0]", "scene.meshes[0].rpy_deg"},
        {"rpy_deg: [0, .nan, 0]", "scene.meshes[0].rpy_deg"},
        {"position: [1, 2, .inf]", "scene.meshes[0].position"},
    };
    for (const auto& c : bad_cases) {
        t.meshes = "- {file: plane.obj, role: seabed, " + c[0] + "}\n";
        EXPECT_EQ(errorField(t.yaml()), c[1]) << c[0];
    }
}

TEST_F(ScenarioTest, UnknownKeyNamesTheField) {
    TinyScenario t = tiny();
    t.extra = "fls: {range_maxx: 12}\n";
    EXPECT_EQ(errorField(t.yaml()), "fls.range_maxx");
    t.extra = "colour: blue\n";
    EXPECT_EQ(errorField(t.yaml()), "colour");
}

TEST_F(ScenarioTest, NegativeRangeNamesTheField) {
    TinyScenario t = tiny();
    t.extra = "fls: {range_min: -1}\n";
    EXPECT_EQ(errorField(t.yaml()), "fls.range_min");
    t.extra = "ps: {range_max: -5}\n";
    EXPECT_EQ(errorField(t.yaml()), "ps.range_max");
}

TEST_F(ScenarioTest, EmptyTrajectoryNamesTheField) {
    const std::string base = "scene: {meshes: [{file: plane.obj, role: seabed}]}\n";
    EXPECT_EQ(errorField(base + "trajectory: {passes: []}\n"), "trajectory");
    EXPECT_EQ(errorField(base), "trajectory");
    EXPECT_EQ(errorField(base + "trajectory: {passes: [{sequences: 0}]}\n"), "trajectory.passes[0].sequences");
}

TEST_F(ScenarioTest, OtherBadValuesNameTheField) {
    TinyScenario t = tiny();
    t.meshes = "- {file: plane.obj, role: rock}\n";
    EXPECT_EQ(errorField(t.yaml()), "scene.meshes[0].role");
    t = tiny();
    t.extra = "fls: {beams: many}\n";
    EXPECT_EQ(errorField(t.yaml()), "fls.beams");
    t.extra = "";
    t.noise = "{coherent_fraction: 2}";
    EXPECT_EQ(errorField(t.yaml()), "noise.coherent_fraction");
}

}  // namespace
}  // namespace sonarfusion::sim
