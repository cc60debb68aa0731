// Issue 12 for the scenario: a bad value of each scenario struct (each with
// its own validate(), config/scenario.hpp) stops sf-sim with exit code 2 and a
// message naming the file and the field.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "sim_test_util.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;

const std::string kScene = "scene: {meshes: [{file: plane.obj, role: seabed}]}\n";
const std::string kTrajectory = "trajectory: {passes: [{sequences: 2}]}\n";
const std::string kFast = "fls: {rays_elevation: 16}\n";

struct BadScenario {
    const char* name;  // test name: the struct and the value
    std::string yaml;
    const char* key;
};

void PrintTo(const BadScenario& b, std::ostream* os) { *os << b.yaml; }

const BadScenario kBadScenarios[] = {
    {"Scene_water_impedance", "scene: {water_impedance: 0, meshes: [{file: plane.obj, role: seabed}]}\n" + kTrajectory,
     "scene.water_impedance"},
    {"Mesh_impedance", "scene: {meshes: [{file: plane.obj, role: seabed, impedance: -1}]}\n" + kTrajectory,
     "scene.meshes[0].impedance"},
    {"FlsGeometry_elevation_samples", kScene + kTrajectory + "fls: {elevation_samples: 500}\n",
     "fls.elevation_samples"},
    {"FlsGeometry_range", kScene + kTrajectory + "fls: {range_min: 5, range_max: 4}\n", "fls.range_max"},
    {"FlsSim_rays_azimuth", kScene + kTrajectory + "fls: {rays_azimuth: 0}\n", "fls.rays_azimuth"},
    {"FlsMount_z_nan", kScene + kTrajectory + "fls: {mount: {z: .nan}}\n", "fls.mount.z"},
    {"PsGeometry_range_min", kScene + kTrajectory + "ps: {range_min: -2}\n", "ps.range_min"},
    {"PsGeometry_fan", kScene + kTrajectory + "ps: {fan_min_deg: 5, fan_max_deg: 5}\n", "ps.fan_max_deg"},
    {"PsSim_head_step", kScene + kTrajectory + "ps: {head_step_deg: 0}\n", "ps.head_step_deg"},
    {"Noise_scatterers", kScene + kTrajectory + "noise: {scatterers: 0}\n", "noise.scatterers"},
    {"Navigation_latency", kScene + kTrajectory + "navigation: {latency: -1}\n", "navigation.latency"},
    {"Motion_period", kScene + kTrajectory + "motion: {roll_amplitude_deg: 3, period: 0}\n", "motion.period"},
    {"Pass_altitude", kScene + "trajectory: {passes: [{sequences: 2, altitude: 0}]}\n",
     "trajectory.passes[0].altitude"},
    {"Waypoints_step", kScene + "trajectory: {waypoints: [{step: 0, points: [[0, 0, 17], [1, 0, 17]]}]}\n",
     "trajectory.waypoints[0].step"},
    {"Trajectory_period", kScene + "trajectory: {sequence_period: 0, passes: [{sequences: 2}]}\n",
     "trajectory.sequence_period"},
    {"Channels_empty", kScene + kTrajectory + "channels: {nav: ''}\n", "channels.nav"},
    // Across blocks (Scenario::validate): the truth channel must be its own.
    {"Scenario_truth_channel", kScene + kTrajectory + "navigation: {latency: 0.05}\nchannels: {nav_truth: NAV}\n",
     "channels.nav_truth"},
};

class ScenarioValidateCli : public ::testing::TestWithParam<BadScenario> {
protected:
    void SetUp() override { saveObj(test::flatPlane(20.0), dir.file("plane.obj")); }
    int runSim(const std::string& scenario, std::string& err) const {
        const std::string err_path = dir.file("stderr.txt");
        const std::string cmd = std::string(SF_SIM_EXE) + " --quiet --scenario " + scenario + " --log " +
                                dir.file("x.lcmlog") + " 2> " + err_path;
        const int status = std::system(cmd.c_str());
        err = test::readBytes(err_path);
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    TempDir dir;
};

TEST_P(ScenarioValidateCli, BadValueNamesFileAndFieldExitTwo) {
    const BadScenario& b = GetParam();
    const std::string path = dir.file("bad.yaml");
    test::writeText(path, b.yaml + kFast);
    std::string err;
    EXPECT_EQ(runSim(path, err), 2) << b.yaml << err;
    EXPECT_NE(err.find(path + ": scenario field '" + b.key + "': "), std::string::npos) << b.yaml << err;
}

INSTANTIATE_TEST_SUITE_P(EveryStruct, ScenarioValidateCli, ::testing::ValuesIn(kBadScenarios),
                         [](const ::testing::TestParamInfo<BadScenario>& i) { return std::string(i.param.name); });

// The control: the base scenario of the cases above simulates (exit 0), so
// each case fails on its value.
TEST(ScenarioValidateControl, TheBaseScenarioSimulates) {
    TempDir dir;
    saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
    test::writeText(dir.file("ok.yaml"), kScene + kTrajectory + kFast + "navigation: {latency: 0.05}\n");
    const std::string cmd =
        std::string(SF_SIM_EXE) + " --quiet --scenario " + dir.file("ok.yaml") + " --log " + dir.file("x.lcmlog");
    EXPECT_EQ(std::system(cmd.c_str()), 0);
}

}  // namespace
}  // namespace sonarfusion::sim
