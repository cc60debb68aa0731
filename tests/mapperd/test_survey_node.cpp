// Survey mode in the daemon core (issue 13): two boxes 30 m apart on one line
// give two maps; the first is finalised when the vehicle has left it, handed
// to Publisher::finalised and freed; MAPPER_STATUS lists the maps being made.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

#include "map_file.hpp"
#include "mapper_node.hpp"
#include "survey_output.hpp"
#include "node_test_util.hpp"
#include "../unit/test_helpers.hpp"

using namespace sonarfusion;
using sonarfusion::test::send;

namespace {
// NAV at 20 Hz, 1 cm per step from x = -6 m heading north, and the PS pings of
// the box world of the unit tests (2 x 1.2 x 1 m boxes at x = 0 and 30 m).
void stream(MapperNode& node, int from, int to) {
    const MapperConfig& c = node.mapper().config();
    static const sonarfusion::test::BoxesWorld world{0.0, 30.0};
    for (int i = from; i < to; ++i) {
        const int64_t t = 1000000 + int64_t{i} * 50000;
        const TimedPose pose = sonarfusion::test::trackPose(t, -6.0 + 0.01 * i);
        nav_state_t n{};
        n.utime = t;
        n.seq = i;
        for (int k = 0; k < 3; ++k) n.position_ned[k] = pose.pose.position[k];
        send(node, "NAV", n);
        const int phase = i % 80;
        const double head = (phase < 40 ? -20 + phase : 60 - phase) * kDegToRad;
        const auto sim = sonarfusion::test::simulatePing(world, node.mapper().psModel(), pose.pose, t, head);
        ps_ping_t p = sonarfusion::test::psPing(c, t + 10000, i, head);
        p.num_bins = static_cast<int32_t>(sim.bins.size());
        p.intensity.assign(sim.bins.begin(), sim.bins.end());
        send(node, "PS", p);
    }
}
}  // namespace

TEST(SurveyNode, TwoMapsTheFirstFinalisedWhenLeftBothListedInStatus) {
    DaemonConfig cfg;
    std::vector<int> finalised;
    std::vector<int> objects_map_ids;
    MapperNode::Publisher pub;
    pub.finalised = [&](const FinalisedMap& f) {
        finalised.push_back(f.map_id);
        EXPECT_TRUE(f.map.initialised());  // handed over before the slot is freed
    };
    pub.objects = [&](const objects_t& m) {
        for (const object_t& o : m.objects) objects_map_ids.push_back(o.map_id);
    };
    MapperNode node(cfg, pub);
    stream(node, 0, 1700);  // x = 11 m: the first map is being made
    {
        const mapper_status_t& s = node.status();
        ASSERT_EQ(s.num_maps, 1);
        EXPECT_EQ(s.map_ids[0], 1);
        EXPECT_NEAR(s.map_centre_north[0], 0.0, 1.5);
        EXPECT_GT(s.map_updates[0], 0);
        EXPECT_EQ(s.maps_finalised, 0);
    }
    stream(node, 1700, 3800);  // x = 32 m: left the first map, anchored the second
    ASSERT_EQ(finalised, std::vector<int>{1});
    {
        const mapper_status_t& s = node.status();
        ASSERT_EQ(s.num_maps, 1);
        EXPECT_EQ(s.map_ids[0], 2);
        EXPECT_NEAR(s.map_centre_north[0], 30.0, 1.5);
        EXPECT_EQ(s.maps_finalised, 1);
        EXPECT_EQ(s.detection_no_free_map, 0);
    }
    node.flush(true);
    node.finish();
    EXPECT_EQ(finalised, (std::vector<int>{1, 2}));
    EXPECT_EQ(node.status().num_maps, 0);
    EXPECT_EQ(node.status().maps_finalised, 2);
    for (int id : objects_map_ids) EXPECT_TRUE(id == 1 || id == 2);
}

TEST(SurveyNode, AFullPoolCountsAndKeepsItsMap) {
    DaemonConfig cfg;
    cfg.mapper.survey.max_maps = 1;
    cfg.mapper.survey.release_margin = 100.0;  // never left
    std::vector<int> finalised;
    MapperNode::Publisher pub;
    pub.finalised = [&](const FinalisedMap& f) { finalised.push_back(f.map_id); };
    MapperNode node(cfg, pub);
    stream(node, 0, 3800);
    EXPECT_TRUE(finalised.empty());
    const mapper_status_t& s = node.status();
    ASSERT_EQ(s.num_maps, 1);
    EXPECT_EQ(s.map_ids[0], 1);
    EXPECT_GT(s.detection_no_free_map, 0);
    node.finish();
    EXPECT_EQ(finalised, std::vector<int>{1});
}

// sf-mapper's writer: each finalised map lands in --map-dir whole (map file
// that loads back equal, PLY, objects with their voxels) and no temporary is
// left; a folder that cannot be written is counted, and mapping goes on.
TEST(SurveyNode, FinalisedMapsAreWrittenWholeAndAFailedWriteIsCounted) {
    const std::string dir = "/tmp/sf_survey_" + std::to_string(getpid());
    ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
    DaemonConfig cfg;
    MapOutputs outs{dir + "/first.map", dir};
    std::vector<std::vector<float>> at_finalisation;
    MapperNode::Publisher pub;
    pub.finalised = [&](const FinalisedMap& f) {
        at_finalisation.push_back(f.map.logOddsData());
        onFinalised(f, cfg, outs);
    };
    MapperNode node(cfg, pub);
    stream(node, 0, 3800);
    node.flush(true);
    node.finish();
    ASSERT_EQ(at_finalisation.size(), 2u);
    EXPECT_EQ(outs.write_failures, 0);
    for (int id : {1, 2}) {
        const std::string base = dir + "/map_" + std::to_string(id);
        VoxelMap m(cfg.mapper.map);
        (void)loadMap(base + ".map", m);
        EXPECT_EQ(m.logOddsData(), at_finalisation[static_cast<std::size_t>(id - 1)]) << id;
        std::ifstream json(base + ".objects.json");
        const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
        EXPECT_NE(text.find("\"map_id\": " + std::to_string(id)), std::string::npos);
        EXPECT_NE(text.find("\"voxels\": ["), std::string::npos);
        EXPECT_EQ(text.back(), '\n');  // complete
        EXPECT_TRUE(std::ifstream(base + ".map.ply").good());
    }
    VoxelMap first(cfg.mapper.map);
    (void)loadMap(dir + "/first.map", first);
    EXPECT_EQ(first.logOddsData(), at_finalisation[0]);  // --map-out holds the first map
    EXPECT_NE(std::system(("ls " + dir + " | grep -q tmp").c_str()), 0) << "a temporary was left";

    MapOutputs bad{"", dir + "/missing/folder"};
    int calls = 0;
    MapperNode::Publisher pub2;
    pub2.finalised = [&](const FinalisedMap& f) {
        ++calls;
        onFinalised(f, cfg, bad);
    };
    MapperNode node3(cfg, pub2);
    stream(node3, 0, 3800);
    node3.finish();
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(bad.write_failures, 2);
    EXPECT_EQ(std::system(("rm -rf " + dir).c_str()), 0);
}
