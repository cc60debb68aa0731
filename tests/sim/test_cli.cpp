// The sf-sim command line: exit codes, error messages naming the field, logs
// byte-identical across runs and thread counts, PNG output.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

#include "sim_test_util.hpp"

namespace sonarfusion::sim {
namespace {

using test::TempDir;
using test::TinyScenario;

struct CliRun {
    int exit_code;
    std::string err;
};

CliRun runSim(const TempDir& dir, const std::string& args) {
    const std::string err = dir.file("stderr.txt");
    const std::string cmd = std::string(SF_SIM_EXE) + " " + args + " 2> " + err;
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::readBytes(err)};
}

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
        TinyScenario t;
        t.meshes = "- {file: plane.obj, role: seabed}\n";
        t.sequences = 9;
        t.noise = "{speckle: true}";
        t.extra = "fls: {rays_elevation: 64}\n";
        test::writeText(dir.file("good.yaml"), t.yaml());
    }
    TempDir dir;
};

TEST_F(CliTest, BadScenarioExitsNonZeroNamingTheField) {
    TinyScenario t;
    t.meshes = "- {file: missing.obj, role: seabed}\n";
    test::writeText(dir.file("bad.yaml"), t.yaml());
    CliRun r = runSim(dir, "--scenario " + dir.file("bad.yaml") + " --log " + dir.file("x.lcmlog"));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("scene.meshes[0].file"), std::string::npos) << r.err;

    t.meshes = "- {file: plane.obj, role: seabed}\n";
    t.extra = "ps: {range_min: -2}\n";
    test::writeText(dir.file("bad.yaml"), t.yaml());
    r = runSim(dir, "--scenario " + dir.file("bad.yaml") + " --log " + dir.file("x.lcmlog"));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("ps.range_min"), std::string::npos) << r.err;

    r = runSim(dir, "--scenario " + dir.file("nothing-here.yaml") + " --log " + dir.file("x.lcmlog"));
    EXPECT_NE(r.exit_code, 0);
    r = runSim(dir, "--scenario " + dir.file("good.yaml"));  // no output chosen
    EXPECT_NE(r.exit_code, 0);
}

TEST_F(CliTest, BadNavigationOrMotionExitsTwoNamingTheField) {
    TinyScenario t;
    t.meshes = "- {file: plane.obj, role: seabed}\n";
    t.extra = "navigation: {heading_noise_deg: -0.2}\n";
    test::writeText(dir.file("bad.yaml"), t.yaml());
    CliRun r = runSim(dir, "--scenario " + dir.file("bad.yaml") + " --log " + dir.file("x.lcmlog"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("navigation.heading_noise_deg"), std::string::npos) << r.err;
    t.extra = "motion: {roll_amplitude_deg: 3, period: 0}\n";
    test::writeText(dir.file("bad.yaml"), t.yaml());
    r = runSim(dir, "--scenario " + dir.file("bad.yaml") + " --log " + dir.file("x.lcmlog"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("motion.period"), std::string::npos) << r.err;
}

TEST_F(CliTest, TruthChannelOnlyWithNavErrorsOrMotion) {
    TinyScenario t;
    t.meshes = "- {file: plane.obj, role: seabed}\n";
    t.sequences = 5;
    t.extra = "fls: {rays_elevation: 16}\nnavigation: {latency: 0.05}\n";
    test::writeText(dir.file("lag.yaml"), t.yaml());
    ASSERT_EQ(runSim(dir, "--quiet --scenario " + dir.file("lag.yaml") + " --nav-truth-channel TRUE_POSE --log " +
                              dir.file("lag.lcmlog"))
                  .exit_code,
              0);
    const std::string lag = test::readBytes(dir.file("lag.lcmlog"));
    EXPECT_NE(lag.find("TRUE_POSE"), std::string::npos);
    EXPECT_EQ(lag.find("NAV_TRUTH"), std::string::npos);
    ASSERT_EQ(runSim(dir, "--quiet --scenario " + dir.file("good.yaml") + " --log " + dir.file("good.lcmlog")).exit_code, 0);
    EXPECT_EQ(test::readBytes(dir.file("good.lcmlog")).find("NAV_TRUTH"), std::string::npos);
}

TEST_F(CliTest, LogsAreByteIdenticalAcrossRunsAndThreadCounts) {
    const std::string scenario = "--quiet --scenario " + dir.file("good.yaml");
    ASSERT_EQ(runSim(dir, scenario + " --threads 1 --log " + dir.file("a.lcmlog")).exit_code, 0);
    ASSERT_EQ(runSim(dir, scenario + " --threads 2 --log " + dir.file("b.lcmlog")).exit_code, 0);
    ASSERT_EQ(runSim(dir, scenario + " --seed 99 --log " + dir.file("c.lcmlog")).exit_code, 0);
    const std::string a = test::readBytes(dir.file("a.lcmlog"));
    EXPECT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == test::readBytes(dir.file("b.lcmlog")));
    EXPECT_FALSE(a == test::readBytes(dir.file("c.lcmlog")));
    EXPECT_EQ(a.size(), test::readBytes(dir.file("c.lcmlog")).size());
}

TEST_F(CliTest, WritesPngsOfFlsAndPs) {
    const CliRun r = runSim(dir, "--quiet --scenario " + dir.file("good.yaml") + " --png-dir " + dir.file("png") +
                                  " --png-seq 5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* name : {"fls_polar_5.png", "fls_fan_5.png", "ps_sweep_5.png", "ps_ping_5.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir.file(std::string("png/") + name))) << name;
}

}  // namespace
}  // namespace sonarfusion::sim
