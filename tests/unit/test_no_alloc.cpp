// Proves that the mapper allocates nothing on the heap after construction:
// global operator new is replaced by a counting one in this binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "sonarfusion/mapper.hpp"
#include "test_helpers.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
    if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace sonarfusion;

namespace {
// One straight pass from x = -6 m, 5 mm per step: NAV and a PS ping (sector
// scan -20..20 deg) every step, an FLS frame every 4th. Prepared before
// counting starts: only the mapper is measured.
struct Pass {
    std::vector<TimedPose> navs;
    std::vector<test::OwnedPing> pings;
    std::vector<test::OwnedFrame> frames;
};
template <class World>
Pass preparePass(const World& world, const Mapper& mapper, int steps) {
    Pass pass;
    for (int i = 0; i < steps; ++i) {
        const int64_t t = 1000000 + i * 50000LL;
        pass.navs.push_back(test::trackPose(t, -6.0 + 0.005 * i));
        pass.pings.push_back(
            test::simulatePing(world, mapper.psModel(), pass.navs.back().pose, t, test::sectorScanHead(i)));
        if (i % 4 == 0)
            pass.frames.push_back(
                test::simulateFrame(world, mapper.config().fls, mapper.flsModel(), pass.navs.back().pose, t));
    }
    for (auto& p : pass.pings) p.view.intensity = p.bins.data();  // vectors moved: re-point the views
    for (auto& f : pass.frames) f.view.data = f.pixels.data();
    return pass;
}
}  // namespace

TEST(NoAllocation, ProcessingFramesPingsAndSegmentationAllocatesNothing) {
    Mapper mapper{MapperConfig{}};
    test::BoxWorld world;
    const int steps = 1600;
    const Pass pass = preparePass(world, mapper, steps);
    const auto& navs = pass.navs;
    const auto& pings = pass.pings;
    const auto& frames = pass.frames;

    g_allocations = 0;
    g_counting = true;
    for (int i = 0; i < steps; ++i) {
        mapper.addNav(navs[i]);
        mapper.addPs(pings[i].view);
        if (i % 4 == 0) mapper.addFls(frames[i / 4].view);
        if (i % 400 == 399) mapper.segment();
    }
    g_counting = false;

    EXPECT_EQ(g_allocations.load(), 0);
    // And the run did real work, so the zero above means something.
    EXPECT_TRUE(mapper.map().initialised());
    EXPECT_GT(mapper.counters().fls_used, 100);
    EXPECT_GT(mapper.counters().ps_used, 1000);
    EXPECT_GE(mapper.segmenter().objects().size(), 1u);
}

// Survey mode: two boxes 25 m apart, a second map anchored, the first
// finalised and freed on the way, all without allocating; each new map is
// carved with the held PS pings (detector.replay_pings) from a ring sized here.
TEST(NoAllocation, ASurveyAnchoringFinalisingAndFreeingMapsAllocatesNothing) {
    MapperConfig cfg;
    cfg.segmentation.seabed_from_ps_echoes = false;
    cfg.detector.replay_pings = 1024;
    Mapper mapper{cfg};
    const test::BoxesWorld world{0.0, 25.0};
    const int steps = 7400;
    const Pass pass = preparePass(world, mapper, steps);
    const auto& navs = pass.navs;
    const auto& pings = pass.pings;
    const auto& frames = pass.frames;

    std::size_t published = 0;
    auto finaliseLeft = [&] {
        for (int s = mapper.leavingSlot(); s >= 0; s = mapper.leavingSlot()) {
            published += mapper.finaliseSlot(s).size();
            mapper.releaseSlot(s);
        }
    };
    g_allocations = 0;
    g_counting = true;
    for (int i = 0; i < steps; ++i) {
        mapper.addNav(navs[i]);
        finaliseLeft();
        mapper.addPs(pings[i].view);
        if (i % 4 == 0) mapper.addFls(frames[i / 4].view);
    }
    mapper.leaveAll();
    finaliseLeft();
    g_counting = false;

    EXPECT_EQ(g_allocations.load(), 0);
    EXPECT_EQ(mapper.counters().map_initialisations, 2);
    EXPECT_EQ(mapper.counters().maps_finalised, 2);
    EXPECT_GT(mapper.counters().ps_pings_replayed, 0);
    EXPECT_GE(published, 2u);
}

// Per-ping FLS geometry: the range window changes mid-pass and back, with a
// cache of two (the configured geometry and one other), so tables are rebuilt
// and a geometry evicted, all in memory allocated at construction.
TEST(NoAllocation, FlsGeometryChangesAndEvictionsAllocateNothing) {
    MapperConfig cfg;
    cfg.fls_max_geometries = 2;
    Mapper mapper{cfg};
    test::BoxWorld world;
    mapper.initialiseMapAt(Eigen::Vector3d(0.0, 0.0, 19.0));
    // Three windows: the configured 0.83-10 m, 0.83-7 m and 1-5 m, in float32 as a message carries them.
    std::vector<FlsGeometry> windows(3);
    windows[1].range_max = 7.0;
    windows[2].range_min = 1.0;
    windows[2].range_max = 5.0;
    std::vector<std::vector<float>> ranges(3), bearings(3);
    for (int w = 0; w < 3; ++w) {
        const FlsModel m{windows[w]};
        for (int r = 0; r < m.rows(); ++r) ranges[w].push_back(static_cast<float>(m.rangeOfRow(r)));
        for (int c = 0; c < m.cols(); ++c) bearings[w].push_back(static_cast<float>(m.bearingOfColumn(c)));
    }
    const int steps = 120;
    std::vector<TimedPose> navs;
    std::vector<test::OwnedFrame> frames;
    std::vector<int> window_of;
    for (int i = 0; i < steps; ++i) {
        const int64_t t = 1000000 + i * 200000LL;
        navs.push_back(test::trackPose(t, -6.0 + 0.02 * i));
        const int w = (i / 10) % 3;  // 10 frames per window, cycling: every change after the second evicts
        const FlsModel m{windows[w]};
        frames.push_back(test::simulateFrame(world, windows[w], m, navs.back().pose, t));
        window_of.push_back(w);
    }
    for (int i = 0; i < steps; ++i) {
        FlsFrame& f = frames[i].view;
        f.data = frames[i].pixels.data();
        f.row_range = ranges[window_of[i]].data();
        f.beam_bearing = bearings[window_of[i]].data();
        f.elevation_min = static_cast<float>(windows[0].elevation_min);
        f.elevation_max = static_cast<float>(windows[0].elevation_max);
    }
    mapper.addNav(navs[0]);

    g_allocations = 0;
    g_counting = true;
    int used = 0;
    for (int i = 1; i < steps; ++i) {
        mapper.addNav(navs[i]);
        used += mapper.addFls(frames[i - 1].view) == Outcome::Used;
    }
    g_counting = false;

    EXPECT_EQ(g_allocations.load(), 0);
    EXPECT_EQ(used, steps - 1);
    // Windows 1 and 2 share the one free slot: each change between them rebuilds.
    EXPECT_GE(mapper.counters().fls_geometry_builds, 7);
    EXPECT_GE(mapper.counters().fls_geometry_evictions, 6);
}

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
