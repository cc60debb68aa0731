// Survey mode (issue 13): a pool of maps that follows the vehicle. Boxes along
// one straight track, each 2.0 x 1.2 x 1.0 m on a flat seabed (test_helpers.hpp).
#include <gtest/gtest.h>

#include <vector>

#include "sonarfusion/mapper.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {

struct Published {
    int map_id;
    ObjectInfo object;
};

// Finalises what the vehicle has left, as the daemon does after each NAV.
void finaliseLeft(Mapper& m, std::vector<Published>& out) {
    for (int s = m.leavingSlot(); s >= 0; s = m.leavingSlot()) {
        const int id = m.slot(s).id;
        for (const ObjectInfo& o : m.finaliseSlot(s)) out.push_back({id, o});
        m.releaseSlot(s);
    }
}

// A straight pass north from start_x: NAV + PS every 5 mm, FLS every 4th step.
void runPass(Mapper& m, const test::BoxesWorld& w, double start_x, double length, int64_t t0,
             std::vector<Published>& out) {
    const int steps = static_cast<int>(length / 0.005);
    for (int i = 0; i < steps; ++i) {
        const int64_t t = t0 + i * 50000LL;
        const TimedPose nav = test::trackPose(t, start_x + 0.005 * i);
        m.addNav(nav);
        finaliseLeft(m, out);
        auto ping = test::simulatePing(w, m.psModel(), nav.pose, t, test::sectorScanHead(i));
        m.addPs(ping.view);
        if (i % 4 == 0) {
            auto frame = test::simulateFrame(w, m.config().fls, m.flsModel(), nav.pose, t);
            m.addFls(frame.view);
        }
    }
}

MapperConfig surveyConfig() {
    MapperConfig cfg;
    cfg.segmentation.seabed_from_ps_echoes = false;  // as in test_mapper.cpp: this PS never sees the seabed beside a box
    return cfg;
}
}  // namespace

TEST(Survey, ADetectionFarAwayAnchorsASecondMapOneInsideDoesNot) {
    Mapper m(surveyConfig());
    const test::BoxesWorld world{0.0, 25.0};
    std::vector<Published> out;
    runPass(m, world, -6.0, 37.0, 1000000, out);
    const MapperCounters& c = m.counters();
    // Two maps, one per box; the box's later detections fell inside its map.
    EXPECT_EQ(c.map_initialisations, 2);
    EXPECT_GT(c.detection_in_active_map, 0);
    EXPECT_EQ(c.detection_no_free_map, 0);
    // The first map was left (the vehicle went on 25 m) and finalised on the way.
    EXPECT_EQ(c.maps_finalised, 1);
    ASSERT_EQ(m.activeMaps(), 1);
    m.leaveAll();
    finaliseLeft(m, out);
    EXPECT_EQ(m.activeMaps(), 0);
    EXPECT_EQ(c.maps_finalised, 2);
    // Each map published its own box, once.
    int near_first = 0, near_second = 0;
    for (const Published& p : out) {
        const double x = p.object.centroid.x();
        if (p.object.voxel_count < 100) continue;  // FLS scraps beside a box
        if (std::fabs(x) < 1.5) {
            ++near_first;
            EXPECT_EQ(p.map_id, 1);
        } else if (std::fabs(x - 25.0) < 1.5) {
            ++near_second;
            EXPECT_EQ(p.map_id, 2);
        }
        EXPECT_TRUE(p.object.ps_confirmed);
    }
    EXPECT_EQ(near_first, 1);
    EXPECT_EQ(near_second, 1);
}

TEST(Survey, AFullPoolCountsTheDetectionAndNeverEvicts) {
    MapperConfig cfg = surveyConfig();
    cfg.survey.max_maps = 1;
    Mapper m(cfg);
    // The second box 12 m on: the vehicle is still within reach of the first map.
    const test::BoxesWorld world{0.0, 12.0};
    std::vector<Published> out;
    runPass(m, world, -6.0, 20.0, 1000000, out);
    const MapperCounters& c = m.counters();
    EXPECT_EQ(c.map_initialisations, 1);
    EXPECT_GT(c.detection_no_free_map, 0);
    EXPECT_EQ(c.maps_finalised, 0);
    ASSERT_EQ(m.activeMaps(), 1);
    EXPECT_EQ(m.slot(0).id, 1);  // still the first map
    EXPECT_LT(std::fabs(m.map().centre().x()), 2.0);
}

TEST(Survey, ALaterPassOverAPublishedObjectMapsItNoMoreAndPublishesItOnce) {
    MapperConfig cfg = surveyConfig();
    cfg.survey.reopen_on_revisit = false;  // the map is freed when finalised
    Mapper m(cfg);
    const test::BoxesWorld world{0.0};
    std::vector<Published> out;
    runPass(m, world, -6.0, 24.0, 1000000, out);  // leaves the map: finalised on the way
    ASSERT_EQ(m.counters().maps_finalised, 1);
    runPass(m, world, -6.0, 24.0, 1000000 + 24 * 10000000LL, out);  // the same line again
    m.leaveAll();
    finaliseLeft(m, out);
    const MapperCounters& c = m.counters();
    EXPECT_GT(c.detection_known_object, 0);
    EXPECT_EQ(c.map_initialisations, 1);
    int boxes = 0;
    for (const Published& p : out) boxes += p.object.voxel_count >= 100 && std::fabs(p.object.centroid.x()) < 1.5;
    EXPECT_EQ(boxes, 1);
}

// survey.reopen_on_revisit (default): the finalised map stays in its slot, and
// a later line that detects its object reopens it, so both lines' evidence
// lands in one map, which publishes the object again (same map id), once.
TEST(Survey, ALaterPassOverAFinalisedMapReopensItAndItsObjectStaysOne) {
    Mapper m(surveyConfig());
    const test::BoxesWorld world{0.0};
    std::vector<Published> out;
    runPass(m, world, -6.0, 24.0, 1000000, out);  // leaves the map: finalised on the way, parked
    ASSERT_EQ(m.counters().maps_finalised, 1);
    EXPECT_EQ(m.activeMaps(), 0);
    ASSERT_TRUE(m.slot(0).parked);
    const int64_t updates_first = m.slot(0).updates;
    const int first_objects = static_cast<int>(out.size());
    runPass(m, world, -6.0, 24.0, 1000000 + 24 * 10000000LL, out);  // the same line again
    m.leaveAll();
    finaliseLeft(m, out);
    const MapperCounters& c = m.counters();
    EXPECT_EQ(c.detection_reopened_map, 1);
    EXPECT_EQ(c.detection_known_object, 0);
    EXPECT_EQ(c.map_initialisations, 1);  // no second map
    EXPECT_EQ(c.maps_finalised, 2);       // the same map, finalised again
    EXPECT_GT(m.slot(0).updates, updates_first) << "the second line's sonar data went into the reopened map";
    // Published again by the reopened map (id 1), not refused as a duplicate of its own earlier box.
    int again = 0;
    for (std::size_t i = static_cast<std::size_t>(first_objects); i < out.size(); ++i)
        again += out[i].map_id == 1 && out[i].object.voxel_count >= 100 && std::fabs(out[i].object.centroid.x()) < 1.5;
    EXPECT_EQ(again, 1);
    EXPECT_EQ(c.objects_duplicate, 0);
}

// A parked map gives its slot to a new object's map (the oldest parked first);
// a map still being made never does (AFullPoolCountsTheDetectionAndNeverEvicts).
TEST(Survey, AParkedMapGivesItsSlotToANewMap) {
    MapperConfig cfg = surveyConfig();
    cfg.survey.max_maps = 1;
    Mapper m(cfg);
    const test::BoxesWorld world{0.0, 25.0};
    std::vector<Published> out;
    runPass(m, world, -6.0, 37.0, 1000000, out);
    const MapperCounters& c = m.counters();
    EXPECT_EQ(c.map_initialisations, 2);
    EXPECT_EQ(c.detection_no_free_map, 0);
    EXPECT_EQ(m.slot(0).id, 2);
    EXPECT_FALSE(m.slot(0).parked);
    EXPECT_GT(std::fabs(m.map().centre().x()), 20.0);
}

TEST(Survey, ObjectsAreNeverPublishedTwiceByOverlappingMaps) {
    // Two maps anchored by hand over the same box (as a straddling object
    // would): only one publishes it, the map that sees more of it.
    MapperConfig cfg = surveyConfig();
    Mapper m(cfg);
    const test::BoxesWorld world{0.0};
    std::vector<Published> out;
    runPass(m, world, -6.0, 3.0, 1000000, out);
    ASSERT_EQ(m.activeMaps(), 1);
    // A second map 3 m north of the first, from here on updated as well: both
    // hold the whole box.
    m.initialiseMapAt(m.map().centre() + Eigen::Vector3d(3.0, 0.0, 0.0));
    ASSERT_EQ(m.activeMaps(), 2);
    runPass(m, world, -3.0, 6.0, 1000000 + 600 * 50000LL, out);
    m.leaveAll();
    finaliseLeft(m, out);
    int boxes = 0;
    for (const Published& p : out) boxes += p.object.voxel_count >= 100;
    EXPECT_EQ(boxes, 1);
    EXPECT_EQ(m.counters().maps_finalised, 2);
    EXPECT_GE(m.counters().objects_left_to_other_map + m.counters().objects_duplicate, 1);
}

TEST(Survey, CheckpointCarriesEveryMap) {
    Mapper a(surveyConfig());
    const test::BoxesWorld world{0.0, 25.0};
    std::vector<Published> out;
    runPass(a, world, -6.0, 33.0, 1000000, out);
    ASSERT_EQ(a.counters().map_initialisations, 2);
    std::vector<uint8_t> buf(a.stateBytesBound());
    StateWriter w(buf.data(), buf.size());
    a.saveState(w);
    ASSERT_FALSE(w.overflow());
    Mapper b(surveyConfig());
    StateReader r(buf.data(), w.size());
    ASSERT_TRUE(b.loadState(r));
    EXPECT_TRUE(a.slot(0).parked) << "the first map, finalised on the way, is kept for a revisit";
    for (int s = 0; s < a.slotCount(); ++s) {
        EXPECT_EQ(a.slot(s).id, b.slot(s).id);
        EXPECT_EQ(a.slot(s).parked, b.slot(s).parked);
        EXPECT_EQ(a.slotMap(s).logOddsData(), b.slotMap(s).logOddsData());
        EXPECT_EQ(a.slotMap(s).origin(), b.slotMap(s).origin());
    }
    EXPECT_EQ(a.counters().maps_finalised, b.counters().maps_finalised);
}
