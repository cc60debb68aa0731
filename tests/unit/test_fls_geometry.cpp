// Per-ping FLS geometry (issue 14; docs/algorithm.md, "Per-ping FLS geometry"):
// frames carry their own ranges, bearings and aperture; the mapper caches the
// direction tables of fls.max_geometries geometries (the configured one pinned,
// the others least recently used first) and refuses insane geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sonarfusion/mapper.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

namespace {

// A frame's geometry as fls_image_t carries it (float32), from a FlsGeometry.
struct GeometryArrays {
    std::vector<float> ranges, bearings;
    double elevation_min = 0.0, elevation_max = 0.0;
    explicit GeometryArrays(const FlsGeometry& g) {
        const FlsModel m{g};
        for (int r = 0; r < m.rows(); ++r) ranges.push_back(static_cast<float>(m.rangeOfRow(r)));
        for (int c = 0; c < m.cols(); ++c) bearings.push_back(static_cast<float>(m.bearingOfColumn(c)));
        elevation_min = static_cast<float>(g.elevation_min);
        elevation_max = static_cast<float>(g.elevation_max);
    }
    void attach(FlsFrame& f) const {
        f.row_range = ranges.data();
        f.beam_bearing = bearings.data();
        f.elevation_min = elevation_min;
        f.elevation_max = elevation_max;
    }
};

FlsGeometry window(double range_min, double range_max) {
    FlsGeometry g;
    g.range_min = range_min;
    g.range_max = range_max;
    return g;
}

// A mapper with its map anchored under the track, NAV from t = 0 to 3 s.
struct Fixture {
    Mapper mapper;
    explicit Fixture(const MapperConfig& cfg) : mapper(cfg) {
        mapper.initialiseMapAt(Eigen::Vector3d(0.0, 0.0, 20.0 - 1.0));
        for (int64_t t = 0; t <= 3000000; t += 100000) mapper.addNav(test::trackPose(t, -6.0));
    }
    Outcome frameWith(const GeometryArrays* g, int64_t utime = 1000000) {
        test::OwnedFrame f = test::blankFrame(FlsGeometry{}, utime);
        test::setPixel(f, 100, 48, 220);
        f.view.data = f.pixels.data();
        if (g) g->attach(f.view);
        return mapper.addFls(f.view);
    }
};

}  // namespace

TEST(FlsGeometry, AssignRebuildsTheTablesInPlaceAndSameGeometryFindsThem) {
    FlsModel m{FlsGeometry{}};
    const GeometryArrays config{FlsGeometry{}}, zoom{window(0.83, 7.0)};
    test::OwnedFrame f = test::blankFrame(FlsGeometry{}, 0);
    config.attach(f.view);
    EXPECT_TRUE(m.sameGeometry(f.view));  // float32 of the configured values
    zoom.attach(f.view);
    EXPECT_FALSE(m.sameGeometry(f.view));
    const Eigen::Vector3f* before = m.directions().data();
    ASSERT_TRUE(m.assign(f.view));
    EXPECT_EQ(m.directions().data(), before);  // same storage: nothing allocated
    EXPECT_TRUE(m.sameGeometry(f.view));
    EXPECT_NEAR(m.rangeMax(), 7.0, 1e-6);
    EXPECT_NEAR(m.rangeOfRow(511), 0.83, 1e-6);
    // Larger than the capacity (the configured size): refused, unchanged.
    test::OwnedFrame big = test::blankFrame(window(0.83, 7.0), 0);
    std::vector<float> ranges(600, 1.0f);
    big.view.rows = 600;
    big.view.row_range = ranges.data();
    big.view.beam_bearing = zoom.bearings.data();
    EXPECT_FALSE(m.assign(big.view));
    EXPECT_NEAR(m.rangeMax(), 7.0, 1e-6);
}

TEST(FlsGeometry, ConfiguredGeometryUsesSlotZeroAndBuildsNothing) {
    Fixture fx{MapperConfig{}};
    const GeometryArrays config{FlsGeometry{}};
    EXPECT_EQ(fx.frameWith(&config), Outcome::Used);
    EXPECT_EQ(fx.frameWith(nullptr, 1000001), Outcome::Used);  // no geometry: the configured one
    EXPECT_EQ(fx.mapper.lastFlsGeometrySlot(), 0);
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 0);
}

TEST(FlsGeometry, TwoAlternatingWindowsAreBothMappedWhereTheirRangesSay) {
    Fixture fx{MapperConfig{}};
    const GeometryArrays config{FlsGeometry{}}, zoom{window(0.83, 7.0)};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(fx.frameWith(i % 2 ? &zoom : &config, 1000000 + i), Outcome::Used);
        EXPECT_EQ(fx.mapper.lastFlsGeometrySlot(), i % 2 ? 1 : 0);
    }
    EXPECT_EQ(fx.mapper.counters().fls_used, 6);
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 1);  // the zoom's tables, once
    EXPECT_EQ(fx.mapper.counters().fls_geometry_evictions, 0);

    // Row 100, beam 48 lies at 8.2 m in the configured window and 5.7 m in the
    // zoomed one: both arcs were voted for.
    const Pose pose = *fx.mapper.navPoseAt(1000000);
    const Eigen::Isometry3d s = sensorToWorld(pose, Mounting{});
    const VoxelMap& map = fx.mapper.map();
    auto touched = [&](const FlsModel& m) {
        VoxelIndex v;
        return map.worldToIndex(s * m.pointInSensor(100, 48, 2), v) && (map.flags(map.linear(v)) & VoxelMap::kFlsTouched) != 0;
    };
    FlsModel zoom_model{window(0.83, 7.0)};
    EXPECT_TRUE(touched(fx.mapper.flsModel()));
    EXPECT_TRUE(touched(zoom_model));
    EXPECT_NEAR(fx.mapper.flsGeometryModel(1).rangeMax(), 7.0, 1e-5);
}

TEST(FlsGeometry, AFullCacheEvictsTheLeastRecentlyUsedGeometry) {
    MapperConfig cfg;
    cfg.fls_max_geometries = 3;  // the configured one + two
    Fixture fx{cfg};
    const GeometryArrays a{window(0.83, 7.0)}, b{window(0.83, 5.0)}, c{window(0.5, 3.0)};
    int64_t t = 1000000;
    EXPECT_EQ(fx.frameWith(&a, t++), Outcome::Used);
    EXPECT_EQ(fx.frameWith(&b, t++), Outcome::Used);
    EXPECT_EQ(fx.frameWith(&a, t++), Outcome::Used);  // a is now the more recent
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 2);
    EXPECT_EQ(fx.frameWith(&c, t++), Outcome::Used);  // evicts b
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 3);
    EXPECT_EQ(fx.mapper.counters().fls_geometry_evictions, 1);
    EXPECT_EQ(fx.frameWith(&a, t++), Outcome::Used);  // still cached
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 3);
    EXPECT_EQ(fx.frameWith(&b, t++), Outcome::Used);  // back, evicting c
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 4);
    EXPECT_EQ(fx.mapper.counters().fls_geometry_evictions, 2);
    std::vector<double> cached;
    for (int s = 1; s < fx.mapper.flsGeometrySlots(); ++s) cached.push_back(fx.mapper.flsGeometryModel(s).rangeMax());
    std::sort(cached.begin(), cached.end());
    ASSERT_EQ(cached.size(), 2u);
    EXPECT_NEAR(cached[0], 5.0, 1e-5);
    EXPECT_NEAR(cached[1], 7.0, 1e-5);
    // The configured geometry is never evicted.
    const GeometryArrays config{FlsGeometry{}};
    EXPECT_EQ(fx.frameWith(&config, t++), Outcome::Used);
    EXPECT_EQ(fx.mapper.lastFlsGeometrySlot(), 0);
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 4);
}

TEST(FlsGeometry, OneGeometryRefusesEveryOtherAndCountsIt) {
    MapperConfig cfg;
    cfg.fls_max_geometries = 1;
    Fixture fx{cfg};
    const GeometryArrays config{FlsGeometry{}}, zoom{window(0.83, 7.0)};
    EXPECT_EQ(fx.frameWith(&zoom), Outcome::FlsGeometryNotCached);
    EXPECT_EQ(fx.frameWith(&config, 1000001), Outcome::Used);
    EXPECT_EQ(fx.mapper.counters().by_outcome[static_cast<int>(Outcome::FlsGeometryNotCached)], 1);
    EXPECT_EQ(outcomeName(Outcome::FlsGeometryNotCached), "fls_geometry_not_cached");
}

TEST(FlsGeometry, InsaneGeometryIsRefusedAsBadGeometry) {
    Fixture fx{MapperConfig{}};
    int64_t t = 1000000;
    auto refused = [&](const GeometryArrays& g) { return fx.frameWith(&g, t++) == Outcome::FlsBadGeometry; };
    GeometryArrays longer{window(0.83, 12.0)};  // beyond the configured sonar's 10 m
    EXPECT_TRUE(refused(longer));
    GeometryArrays nan_bearing{FlsGeometry{}};
    nan_bearing.bearings[10] = std::nanf("");
    EXPECT_TRUE(refused(nan_bearing));
    GeometryArrays unordered{window(0.83, 7.0)};
    std::swap(unordered.ranges[5], unordered.ranges[6]);
    EXPECT_TRUE(refused(unordered));
    GeometryArrays negative{window(0.0, 7.0)};
    negative.ranges.back() = -0.1f;
    EXPECT_TRUE(refused(negative));
    GeometryArrays wider{FlsGeometry{}};
    wider.elevation_max = 10.0 * kDegToRad;  // the configured aperture is +-7 deg
    EXPECT_TRUE(refused(wider));
    GeometryArrays inf_elevation{FlsGeometry{}};
    inf_elevation.elevation_min = -INFINITY;
    EXPECT_TRUE(refused(inf_elevation));
    EXPECT_EQ(fx.mapper.counters().by_outcome[static_cast<int>(Outcome::FlsBadGeometry)], 6);
    EXPECT_EQ(fx.mapper.counters().fls_geometry_builds, 0);
    // A narrower aperture (and a shorter window) is a setting, not an error.
    GeometryArrays narrower{window(1.0, 9.0)};
    narrower.elevation_min = -5.0 * kDegToRad;
    narrower.elevation_max = 5.0 * kDegToRad;
    EXPECT_EQ(fx.frameWith(&narrower, t++), Outcome::Used);
    EXPECT_NEAR(fx.mapper.flsGeometryModel(1).elevationMax(), 5.0 * kDegToRad, 1e-6);
    // Only one of the two tables given.
    test::OwnedFrame f = test::blankFrame(FlsGeometry{}, t++);
    f.view.row_range = narrower.ranges.data();
    f.view.elevation_min = narrower.elevation_min;
    f.view.elevation_max = narrower.elevation_max;
    EXPECT_EQ(fx.mapper.addFls(f.view), Outcome::FlsBadGeometry);
}

// The map of a pass whose window changes half-way is as good as the
// fixed-window map; the same zoomed images read with the configured geometry
// (what a mapper that ignores the message's ranges would do) are not.
TEST(FlsGeometry, AWindowChangeMapsTheBoxLikeAFixedWindow) {
    const test::BoxWorld world;
    MapperConfig cfg;
    cfg.update.fls_free_space = false;  // FLS votes alone, no PS: compare what the FLS put where
    const FlsGeometry fixed_g{}, zoom_g = window(0.83, 7.0);
    const FlsModel fixed_m{fixed_g}, zoom_m{zoom_g};
    const GeometryArrays fixed_a{fixed_g}, zoom_a{zoom_g};
    Mapper fixed{cfg}, changed{cfg}, ignored{cfg};
    for (Mapper* m : {&fixed, &changed, &ignored}) m->initialiseMapAt(Eigen::Vector3d(0.0, 0.0, 19.0));
    for (int i = 0; i < 400; ++i) {
        const TimedPose nav = test::trackPose(1000000 + i * 200000LL, -6.0 + 0.02 * i);
        const bool zoomed = i >= 200;
        test::OwnedFrame a = test::simulateFrame(world, fixed_g, fixed_m, nav.pose, nav.utime);
        test::OwnedFrame b = zoomed ? test::simulateFrame(world, zoom_g, zoom_m, nav.pose, nav.utime)
                                    : test::simulateFrame(world, fixed_g, fixed_m, nav.pose, nav.utime);
        a.view.data = a.pixels.data();
        b.view.data = b.pixels.data();
        fixed_a.attach(a.view);
        test::OwnedFrame c = b;
        c.view.data = c.pixels.data();
        (zoomed ? zoom_a : fixed_a).attach(b.view);
        fixed_a.attach(c.view);  // zoomed images, configured geometry
        for (Mapper* m : {&fixed, &changed, &ignored}) m->addNav(nav);
        for (Mapper* m : {&fixed, &changed, &ignored}) m->addNav(test::trackPose(nav.utime + 1000, nav.pose.position.x()));
        ASSERT_EQ(fixed.addFls(a.view), Outcome::Used);
        ASSERT_EQ(changed.addFls(b.view), Outcome::Used);
        ASSERT_EQ(ignored.addFls(c.view), Outcome::Used);
    }
    // Voxels the FLS voted occupied (L > 0.847, p > 0.7), and how many of them
    // lie within 0.15 m of a true surface (the box or the seabed).
    auto near_surface = [&](const Eigen::Vector3d& p) {
        const Eigen::Vector3d lo = world.box_min.array() - 0.15, hi = world.box_max.array() + 0.15;
        const bool in_grown = (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
        const Eigen::Vector3d ilo = world.box_min.array() + 0.15, ihi = world.box_max.array() - 0.15;
        const bool deep_inside = (p.array() > ilo.array()).all() && (p.array() < ihi.array()).all();
        return (in_grown && !deep_inside) || std::fabs(p.z() - world.seabed) <= 0.15;
    };
    auto score = [&](const Mapper& m, int& total) {
        const VoxelMap& map = m.map();
        int on_box = 0;
        total = 0;
        for (std::size_t i = 0; i < map.size(); ++i) {
            if (map.logOdds(i) <= 0.847f) continue;
            ++total;
            on_box += near_surface(map.centreOf(map.fromLinear(i)));
        }
        return on_box;
    };
    int n_fixed = 0, n_changed = 0, n_ignored = 0;
    const int box_fixed = score(fixed, n_fixed), box_changed = score(changed, n_changed),
              box_ignored = score(ignored, n_ignored);
    std::printf("fixed %d/%d on the box, changed %d/%d, ignored %d/%d\n", box_fixed, n_fixed, box_changed, n_changed,
                box_ignored, n_ignored);
    ASSERT_GT(box_fixed, 100);
    const double p_fixed = static_cast<double>(box_fixed) / n_fixed, p_changed = static_cast<double>(box_changed) / n_changed,
                 p_ignored = static_cast<double>(box_ignored) / std::max(1, n_ignored);
    EXPECT_GE(p_changed, p_fixed - 0.05);
    EXPECT_GE(box_changed, 0.9 * box_fixed);
    EXPECT_LT(p_ignored, p_fixed - 0.05);  // the test can fail: geometry matters
    EXPECT_EQ(changed.counters().fls_geometry_builds, 1);
}

TEST(FlsGeometry, MaxGeometriesIsValidatedByName) {
    MapperConfig cfg;
    EXPECT_EQ(validateConfig(cfg), "");
    for (int bad : {0, -1, kMaxFlsGeometries + 1}) {
        cfg.fls_max_geometries = bad;
        EXPECT_EQ(validateConfig(cfg), "fls.max_geometries: must be in 1..64");
        EXPECT_THROW(Mapper{cfg}, std::invalid_argument);
    }
    // More geometries cost table memory, counted before anything is allocated.
    MapperConfig one, many;
    one.fls_max_geometries = 1;
    many.fls_max_geometries = 64;
    EXPECT_GT(estimatedMemoryBytes(many), estimatedMemoryBytes(one) + 63u * 300000u);
}

// A beam set and row count changed too (a narrower, coarser mode of the same
// sonar): fewer rows and beams than configured fit the cache; more do not.
TEST(FlsGeometry, AnotherBeamSetAndRowCountAreMappedWithinTheConfiguredSize) {
    Fixture fx{MapperConfig{}};
    FlsGeometry mode = window(0.83, 7.0);
    mode.beams = 48;
    mode.rows = 256;
    mode.fov_horizontal = 14.5 * kDegToRad;
    const GeometryArrays g{mode};
    test::OwnedFrame f = test::blankFrame(mode, 1000000);
    test::setPixel(f, 50, 24, 220);
    f.view.data = f.pixels.data();
    g.attach(f.view);
    EXPECT_EQ(fx.mapper.addFls(f.view), Outcome::Used);
    EXPECT_EQ(fx.mapper.lastFlsGeometrySlot(), 1);
    EXPECT_EQ(fx.mapper.flsGeometryModel(1).cols(), 48);
    EXPECT_EQ(fx.mapper.flsGeometryModel(1).rows(), 256);
    const Pose pose = *fx.mapper.navPoseAt(1000000);
    const FlsModel m{mode};
    VoxelIndex v;
    ASSERT_TRUE(fx.mapper.map().worldToIndex(sensorToWorld(pose, Mounting{}) * m.pointInSensor(50, 24, 2), v));
    EXPECT_NE(fx.mapper.map().flags(fx.mapper.map().linear(v)) & VoxelMap::kFlsTouched, 0);
    // More beams than the configured 96: the tables are not sized for it.
    FlsGeometry wide = window(0.83, 7.0);
    wide.beams = 128;
    const GeometryArrays w{wide};
    test::OwnedFrame big = test::blankFrame(wide, 1000001);
    big.view.data = big.pixels.data();
    w.attach(big.view);
    EXPECT_EQ(fx.mapper.addFls(big.view), Outcome::FlsSizeMismatch);
}
