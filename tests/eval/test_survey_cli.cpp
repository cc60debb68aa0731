// sf-eval --map-dir end to end on a hand-made survey: a small scenario (two
// boxes 30 m apart, one pass over the first), a folder with two map files and
// their objects files (the first box published exactly, a false object, and a
// duplicate of the first box in map 2), run through the sf-eval binary; the
// report's detection counts and per-object entries are checked.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "eval_test_helpers.hpp"
#include "map_file.hpp"

#ifndef SF_EVAL_BIN
#error "SF_EVAL_BIN (the sf-eval executable) must be defined"
#endif

namespace sonarfusion::eval {
namespace {

namespace fs = std::filesystem;

std::vector<std::size_t> cells(const MapFileHeader& h, const Eigen::Vector3i& lo, const Eigen::Vector3i& hi) {
    std::vector<std::size_t> v;
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) v.push_back((static_cast<std::size_t>(z) * h.ny + y) * h.nx + x);
    return v;
}

TEST(SurveyCli, ScoresAHandMadeSurveyFolder) {
    const std::string dir = test::tempDir() + "/survey_cli";
    fs::remove_all(dir);
    fs::create_directories(dir + "/maps");
    // Box A: x, y in [-0.5, 0.5], 0.5 m tall on the seabed at 20 m; box B 30 m north.
    const std::string a = test::writeBox("cli_box_a", {-0.5, -0.5, 19.5}, {0.5, 0.5, 20.0});
    const std::string b = test::writeBox("cli_box_b", {29.5, -0.5, 19.5}, {30.5, 0.5, 20.0});
    const std::string bed = test::writeOff("cli_bed", {{-20, -10, 20.0}, {45, -10, 20.0}, {45, 10, 20.0}, {-20, 10, 20.0}},
                                           {{0, 3, 2, 1}});
    const std::string scenario = dir + "/survey_cli.yaml";
    std::ofstream(scenario) << "name: survey_cli\nseed: 1\nscene:\n  meshes:\n"
                            << "    - {file: " << bed << ", role: seabed}\n"
                            << "    - {file: " << a << ", role: object}\n"
                            << "    - {file: " << b << ", role: object}\n"
                            << "trajectory:\n  passes:\n"
                            << "    - {heading_deg: 0, altitude: 3.12, step: 0.05, sequences: 160, start_offset: 6.0}\n";

    // Two 20^3 maps at 0.1 m centred on box A: origin (-1, -1, 18.75) snapped to the lattice.
    MapConfig cfg;
    cfg.nx = cfg.ny = cfg.nz = 20;
    for (int k : {1, 2}) {
        VoxelMap map(cfg);
        map.initialiseAt(Eigen::Vector3d(0.0, 0.0, 19.75));
        saveMap(dir + "/maps/map_" + std::to_string(k) + ".map", map, "fused");
    }
    const MapFileHeader h = readMapHeader(dir + "/maps/map_1.map");
    const Eigen::Vector3d origin(h.origin[0], h.origin[1], h.origin[2]);
    // Box A's cells in this grid: centres inside [-0.5, 0.5]^2 x [19.5, 20].
    const auto cell = [&](double w, int axis) { return static_cast<int>(std::lround((w - origin[axis]) / h.resolution)); };
    const Eigen::Vector3i lo(cell(-0.5, 0), cell(-0.5, 1), cell(19.5, 2)), hi(cell(0.5, 0) - 1, cell(0.5, 1) - 1, cell(20.0, 2) - 1);
    ASSERT_EQ((hi - lo + Eigen::Vector3i::Ones()).prod(), 10 * 10 * 5);
    const auto objects = [&](int id, const nlohmann::json& list) {
        nlohmann::json j = {{"map_id", id},
                            {"variant", "fused"},
                            {"origin", {origin.x(), origin.y(), origin.z()}},
                            {"resolution", h.resolution},
                            {"dims", {h.nx, h.ny, h.nz}},
                            {"objects", list}};
        std::ofstream(dir + "/maps/map_" + std::to_string(id) + ".objects.json") << j.dump();
    };
    objects(1, {{{"id", 1}, {"voxels", cells(h, lo, hi)}},                                   // box A exactly
                {{"id", 2}, {"voxels", cells(h, {0, 0, 0}, {2, 2, 2})}}});                   // nothing there
    objects(2, {{{"id", 1}, {"voxels", cells(h, lo, Eigen::Vector3i(hi.x(), hi.y(), lo.z()))}}});  // A's top again

    const std::string report = dir + "/report.json";
    const std::string cmd = std::string(SF_EVAL_BIN) + " --scenario " + scenario + " --map-dir " + dir + "/maps --json " +
                            report + " --figures " + dir + "/figures > " + dir + "/stdout.txt 2> " + dir + "/stderr.txt";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(dir + "/stderr.txt").rdbuf();
    const auto r = nlohmann::json::parse(std::ifstream(report));
    EXPECT_EQ(r["mode"], "survey");
    EXPECT_EQ(r["detection"]["true"], 2);
    EXPECT_EQ(r["detection"]["found"], 1);
    EXPECT_EQ(r["detection"]["false"], 2);
    EXPECT_EQ(r["detection"]["duplicates"], 1);
    EXPECT_EQ(r["detection"]["maps"], 2);
    ASSERT_EQ(r["objects"].size(), 2u);
    const auto& oa = r["objects"][0];
    EXPECT_EQ(oa["name"], "cli_box_a");
    EXPECT_TRUE(oa["found"]);
    EXPECT_EQ(oa["map_id"], 1);
    EXPECT_EQ(oa["object_id"], 1);
    EXPECT_DOUBLE_EQ(oa["precision"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(oa["iou"].get<double>(), 1.0);
    EXPECT_GT(oa["recall_visible"].get<double>(), 0.9);  // the whole box published: all it saw
    EXPECT_LT(oa["centroid_error_m"].get<double>(), 1e-9);
    EXPECT_FALSE(r["objects"][1]["found"]);
    EXPECT_TRUE(r["objects"][1]["precision"].is_null());
    EXPECT_EQ(r["predicted"][1]["role"], "false");
    EXPECT_EQ(r["predicted"][2]["role"], "duplicate");
    EXPECT_TRUE(fs::exists(dir + "/figures/map_1/eval_fused_side_objects.png"));
    EXPECT_TRUE(fs::exists(dir + "/figures/survey_map_2_objects.ply"));
    // The table names both objects and the detection line.
    std::stringstream out;
    out << std::ifstream(dir + "/stdout.txt").rdbuf();
    EXPECT_NE(out.str().find("cli_box_b"), std::string::npos);
    EXPECT_NE(out.str().find("detection: 2 true, 1 found, 2 false"), std::string::npos) << out.str();

    // A broken objects file stops sf-eval with exit status 1.
    std::ofstream(dir + "/maps/map_2.objects.json") << "{\"objects\": [{\"id\": 1, \"voxels\": [99999999]}]}";
    EXPECT_NE(std::system(cmd.c_str()), 0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace sonarfusion::eval
