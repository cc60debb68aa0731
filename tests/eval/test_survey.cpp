// Survey scoring (survey.hpp, docs/evaluation.md "Survey scoring"): the
// matching rule on hand-made maps (found, false, duplicate, the one-voxel
// tolerance, ties), the per-object metrics, the map_<k> folder reader against
// real map files, and the per-object visibility against the whole-scene rule.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "eval_test_helpers.hpp"
#include "map_file.hpp"
#include "survey.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {
namespace {

namespace fs = std::filesystem;
using test::grid;
using test::tempDir;

// Cells [lo, hi] (inclusive) of a grid as a mask / as a voxel list.
VoxelMask boxMask(const GridSpec& g, const Eigen::Vector3i& lo, const Eigen::Vector3i& hi) {
    VoxelMask m(g.size(), 0);
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) m[g.linear(x, y, z)] = 1;
    return m;
}

std::vector<std::size_t> boxVoxels(const GridSpec& g, const Eigen::Vector3i& lo, const Eigen::Vector3i& hi) {
    std::vector<std::size_t> v;
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) v.push_back(g.linear(x, y, z));
    return v;
}

PredictedObject object(int id, std::vector<std::size_t> voxels) {
    PredictedObject p;
    p.id = id;
    p.voxels = std::move(voxels);
    p.voxel_count = static_cast<int>(p.voxels.size());
    return p;
}

// A true object occupying cells [lo, hi] of the map's grid; its visible
// surface is its top layer (lowest z: NED, z down).
TrueInGrid truthBox(int index, const GridSpec& g, const Eigen::Vector3i& lo, const Eigen::Vector3i& hi) {
    TrueInGrid t;
    t.true_index = index;
    t.solid = boxMask(g, lo, hi);
    t.visible = boxMask(g, lo, Eigen::Vector3i(hi.x(), hi.y(), lo.z()));
    t.visible_by_run = {t.visible};
    return t;
}

SurveyMap surveyMap(int id, const GridSpec& g) {
    SurveyMap m;
    m.map_id = id;
    m.grid = g;
    m.objects_source = "published";
    return m;
}

SurveyTruth namedTruth(int n) {
    SurveyTruth t;
    t.run_names = {"ps"};
    for (int k = 0; k < n; ++k) {
        SurveyTrueObject o;
        o.name = "object_" + std::to_string(k + 1);
        t.objects.push_back(o);
    }
    return t;
}

const GridSpec kGrid = grid(Eigen::Vector3d::Zero(), 20);

TEST(SurveyMatch, FoundFalseAndDuplicateAcrossMaps) {
    // Map 1: object 1 covers true object 0, object 2 lies on no true object.
    // Map 2: object 1 covers part of true object 0 again (a duplicate),
    //        object 2 covers true object 1. True object 2 is never seen.
    const Eigen::Vector3i a0(2, 2, 2), a1(5, 5, 5), b0(12, 12, 2), b1(15, 15, 5);
    std::vector<SurveyMap> maps = {surveyMap(1, kGrid), surveyMap(2, kGrid)};
    maps[0].truths = {truthBox(0, kGrid, a0, a1)};
    maps[0].objects = {object(1, boxVoxels(kGrid, a0, a1)), object(2, boxVoxels(kGrid, {10, 2, 2}, {11, 3, 3}))};
    maps[1].truths = {truthBox(0, kGrid, a0, a1), truthBox(1, kGrid, b0, b1)};
    maps[1].objects = {object(1, boxVoxels(kGrid, a0, {5, 5, 3})), object(2, boxVoxels(kGrid, b0, b1))};

    const auto as = matchSurvey(maps, 3);
    ASSERT_EQ(as.size(), 4u);
    EXPECT_EQ(as[0].true_index, 0);
    EXPECT_EQ(as[0].role, MatchRole::Match);
    EXPECT_EQ(as[0].overlap, 64u);
    EXPECT_EQ(as[1].true_index, -1);
    EXPECT_EQ(as[1].role, MatchRole::False);
    EXPECT_EQ(as[2].true_index, 0);
    EXPECT_EQ(as[2].role, MatchRole::Duplicate);
    EXPECT_EQ(as[3].true_index, 1);
    EXPECT_EQ(as[3].role, MatchRole::Match);

    const SurveyScore s = scoreSurvey(namedTruth(3), maps);
    EXPECT_EQ(s.truth, 3);
    EXPECT_EQ(s.found, 2);
    EXPECT_EQ(s.false_detections, 2);  // the stray object and the duplicate
    EXPECT_EQ(s.duplicates, 1);
    EXPECT_EQ(s.predicted, 4);
    ASSERT_EQ(s.objects.size(), 3u);
    EXPECT_TRUE(s.objects[0].found);
    EXPECT_EQ(s.objects[0].map_id, 1);
    EXPECT_EQ(s.objects[0].object_id, 1);
    EXPECT_EQ(s.objects[0].duplicates, 1);
    EXPECT_DOUBLE_EQ(*s.objects[0].metrics.precision, 1.0);
    EXPECT_DOUBLE_EQ(*s.objects[0].metrics.recall_visible, 1.0);
    EXPECT_DOUBLE_EQ(*s.objects[0].metrics.chamfer_cm, 0.0);
    EXPECT_TRUE(s.objects[1].found);
    EXPECT_EQ(s.objects[1].map_id, 2);
    EXPECT_FALSE(s.objects[2].found);
    EXPECT_FALSE(s.objects[2].metrics.precision.has_value());

    // The report carries the detection counts and one entry per true object.
    const auto j = nlohmann::json::parse(surveyReportJson("hand_made", s, maps));
    EXPECT_EQ(j["detection"]["true"], 3);
    EXPECT_EQ(j["detection"]["found"], 2);
    EXPECT_EQ(j["detection"]["false"], 2);
    ASSERT_EQ(j["objects"].size(), 3u);
    EXPECT_EQ(j["objects"][0]["map_id"], 1);
    EXPECT_TRUE(j["objects"][2]["precision"].is_null());
    EXPECT_EQ(j["predicted"][2]["role"], "duplicate");
}

TEST(SurveyMatch, OneVoxelToleranceAndNoMore) {
    const Eigen::Vector3i lo(5, 5, 5), hi(8, 8, 8);
    std::vector<SurveyMap> maps = {surveyMap(1, kGrid)};
    maps[0].truths = {truthBox(0, kGrid, lo, hi)};
    // A slab one voxel above the box (face neighbours): within one voxel, a match.
    maps[0].objects = {object(1, boxVoxels(kGrid, {5, 5, 4}, {8, 8, 4}))};
    auto as = matchSurvey(maps, 1);
    EXPECT_EQ(as[0].role, MatchRole::Match);
    EXPECT_EQ(as[0].overlap, 16u);
    // Two voxels above it: nothing within one voxel, a false detection.
    maps[0].objects = {object(1, boxVoxels(kGrid, {5, 5, 3}, {8, 8, 3}))};
    as = matchSurvey(maps, 1);
    EXPECT_EQ(as[0].role, MatchRole::False);
    EXPECT_EQ(as[0].overlap, 0u);
    // Diagonal neighbours (distance sqrt 2) are not within one voxel either.
    maps[0].objects = {object(1, {kGrid.linear(4, 4, 5)})};
    EXPECT_EQ(matchSurvey(maps, 1)[0].role, MatchRole::False);
}

TEST(SurveyMatch, LargestOverlapDecidesAndTiesAreDeterministic) {
    const Eigen::Vector3i a0(2, 2, 2), a1(5, 5, 5), b0(7, 2, 2), b1(10, 5, 5);
    std::vector<SurveyMap> maps = {surveyMap(1, kGrid), surveyMap(2, kGrid)};
    maps[0].truths = {truthBox(0, kGrid, a0, a1), truthBox(1, kGrid, b0, b1)};
    maps[1].truths = maps[0].truths;
    // Straddles both, more of it on true object 1.
    maps[0].objects = {object(1, boxVoxels(kGrid, {5, 2, 2}, {9, 5, 5}))};
    // The same voxels in map 2: equal overlap, so map 1's is the match.
    maps[1].objects = {object(1, boxVoxels(kGrid, {5, 2, 2}, {9, 5, 5}))};
    const auto as = matchSurvey(maps, 2);
    EXPECT_EQ(as[0].true_index, 1);
    EXPECT_EQ(as[0].role, MatchRole::Match);
    EXPECT_EQ(as[1].true_index, 1);
    EXPECT_EQ(as[1].role, MatchRole::Duplicate);
    // A bigger duplicate in a later map wins the match instead.
    maps[1].objects = {object(1, boxVoxels(kGrid, {6, 2, 2}, {10, 5, 5}))};
    const auto bs = matchSurvey(maps, 2);
    EXPECT_EQ(bs[0].role, MatchRole::Duplicate);
    EXPECT_EQ(bs[1].role, MatchRole::Match);
    const SurveyScore s = scoreSurvey(namedTruth(2), maps);
    EXPECT_EQ(s.found, 1);
    EXPECT_EQ(s.false_detections, 1);
    EXPECT_EQ(s.objects[1].map_id, 2);
}

TEST(SurveyMatch, PerObjectMetricsUseThatObjectOnly) {
    // A predicted object = true object 0 plus a 16-voxel fin two voxels away:
    // precision 64/80 against object 0, whatever lies elsewhere in the map.
    const Eigen::Vector3i a0(2, 2, 2), a1(5, 5, 5);
    std::vector<SurveyMap> maps = {surveyMap(1, kGrid)};
    maps[0].truths = {truthBox(0, kGrid, a0, a1), truthBox(1, kGrid, {14, 14, 2}, {16, 16, 4})};
    auto voxels = boxVoxels(kGrid, a0, a1);
    for (std::size_t v : boxVoxels(kGrid, {8, 2, 2}, {8, 5, 5})) voxels.push_back(v);
    maps[0].objects = {object(1, voxels)};
    const SurveyScore s = scoreSurvey(namedTruth(2), maps);
    ASSERT_TRUE(s.objects[0].found);
    EXPECT_DOUBLE_EQ(*s.objects[0].metrics.precision, 64.0 / 80.0);
    EXPECT_DOUBLE_EQ(*s.objects[0].metrics.recall_visible, 1.0);
    EXPECT_FALSE(s.objects[1].found);
    EXPECT_EQ(s.found, 1);
    EXPECT_EQ(s.false_detections, 0);
}

// --- the map_<k> folder, with real map files

std::string saveTestMap(const std::string& dir, int id, const Eigen::Vector3d& centre) {
    MapConfig cfg;
    cfg.nx = cfg.ny = cfg.nz = 20;
    VoxelMap map(cfg);
    map.initialiseAt(centre);
    const std::string path = dir + "/map_" + std::to_string(id) + ".map";
    saveMap(path, map, "fused");
    return path;
}

void writeJson(const std::string& path, const nlohmann::json& j) {
    std::ofstream(path) << j.dump();
}

TEST(SurveyDir, ReadsMapsInIdOrderAndChecksTheObjectsFile) {
    const std::string dir = tempDir() + "/survey_dir";
    fs::remove_all(dir);
    fs::create_directories(dir);
    saveTestMap(dir, 2, Eigen::Vector3d(10.0, 0.0, 20.0));
    saveTestMap(dir, 1, Eigen::Vector3d(0.0, 0.0, 20.0));
    std::ofstream(dir + "/notes.txt") << "not a map";
    const GridSpec g1 = [&] {
        const MapFileHeader h = readMapHeader(dir + "/map_1.map");
        return GridSpec{Eigen::Vector3d(h.origin[0], h.origin[1], h.origin[2]), h.resolution, h.nx, h.ny, h.nz};
    }();
    nlohmann::json j = {{"map_id", 1},
                        {"variant", "fused"},
                        {"origin", {g1.origin.x(), g1.origin.y(), g1.origin.z()}},
                        {"resolution", g1.resolution},
                        {"dims", {20, 20, 20}},
                        {"objects",
                         {{{"id", 1},
                           {"voxel_count", 2},
                           {"volume_m3", 0.002},
                           {"centroid", {0.0, 0.0, 19.5}},
                           {"bbox_min", {0.0, 0.0, 19.4}},
                           {"bbox_max", {0.1, 0.2, 19.6}},
                           {"height_m", 0.3},
                           {"ps_confirmed", true},
                           {"voxels", {5, 7}}}}}};
    writeJson(dir + "/map_1.objects.json", j);

    const auto maps = readSurveyDir(dir);
    ASSERT_EQ(maps.size(), 2u);
    EXPECT_EQ(maps[0].map_id, 1);
    EXPECT_EQ(maps[1].map_id, 2);
    EXPECT_EQ(maps[0].objects_source, "published");
    ASSERT_EQ(maps[0].objects.size(), 1u);
    EXPECT_EQ(maps[0].objects[0].voxels, (std::vector<std::size_t>{5, 7}));
    EXPECT_TRUE(maps[0].objects[0].ps_confirmed);
    EXPECT_EQ(maps[0].grid, g1);
    EXPECT_EQ(maps[1].objects_source, "segmented");  // no objects file
    EXPECT_TRUE(maps[1].objects.empty());
    EXPECT_NE(maps[1].grid.origin, maps[0].grid.origin);

    // Every mismatch with the map file is an error naming the file.
    const auto rejects = [&](nlohmann::json bad, const std::string& what) {
        writeJson(dir + "/map_1.objects.json", bad);
        try {
            (void)readSurveyDir(dir);
            ADD_FAILURE() << "accepted " << what;
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("map_1.objects.json"), std::string::npos) << e.what();
        }
    };
    auto bad = j;
    bad["objects"][0]["voxels"] = {8000};
    rejects(bad, "a voxel outside the grid");
    bad = j;
    bad["origin"][0] = g1.origin.x() + 0.1;
    rejects(bad, "another origin");
    bad = j;
    bad["map_id"] = 2;
    rejects(bad, "another map id");
    bad = j;
    bad["dims"] = {20, 20, 10};
    rejects(bad, "other dims");
    bad = j;
    bad["objects"][0].erase("voxels");
    rejects(bad, "an object without voxels");
    fs::remove_all(dir);
}

// --- visibility per object (poses and occluders within range) against the whole-scene rule

TEST(SurveyTruth, PerObjectVisibilityEqualsTheWholeScene) {
    // Two boxes 12 m apart on a seabed sheet, a pass over both, a range of 5 m.
    const std::string a = test::writeBox("survey_a", {1.0, -0.5, 19.0}, {2.0, 0.5, 20.0});
    const std::string b = test::writeBox("survey_b", {13.0, -0.3, 19.4}, {13.8, 0.3, 20.0});
    const std::string bed = test::writeOff("survey_bed", {{-5, -5, 20.0}, {20, -5, 20.0}, {20, 5, 20.0}, {-5, 5, 20.0}},
                                           {{0, 3, 2, 1}});
    SensorRun run{"fls", SensorFov{-0.3, 0.3, 0.4, 1.0, 0.5, 5.0}, {}};
    for (int k = 0; k <= 200; ++k) {
        SensorPose p;
        p.position = Eigen::Vector3d(-4.0 + 0.1 * k, 0.0, 17.0);
        run.poses.push_back(p);
    }
    VisibilityOptions options;
    options.min_pose_spacing = 0.0;  // keep every pose: thinning starts where the kept list starts
    const SurveyTruth truth = makeSurveyTruth({a, b}, {bed}, {run}, options);
    ASSERT_EQ(truth.objects.size(), 2u);
    EXPECT_EQ(truth.objects[0].name, "survey_a");
    const std::vector<TriangleMesh> objects = {loadMesh(a), loadMesh(b)};
    const std::vector<TriangleMesh> occluders = {objects[0], objects[1], loadMesh(bed)};
    for (int k = 0; k < 2; ++k) {
        const auto whole = sampleVisibleSurface({objects[k]}, occluders, {run}, options);
        const auto& mine = truth.objects[k].samples;
        ASSERT_EQ(whole.size(), mine.size());
        std::size_t seen = 0;
        for (std::size_t i = 0; i < whole.size(); ++i) {
            EXPECT_EQ(whole[i].seen_by, mine[i].seen_by) << "object " << k << " sample " << i;
            seen += mine[i].seen_by != 0;
        }
        EXPECT_GT(seen, 0u);             // each box is partly seen ...
        EXPECT_LT(seen, mine.size());    // ... and partly hidden (its base, its back)
    }
}

}  // namespace
}  // namespace sonarfusion::eval
