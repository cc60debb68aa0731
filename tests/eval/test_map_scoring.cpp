// segmentMap segments a saved map as sf-mapper did: the mapper's config, the
// map's variant preset on top, the seabed averaged along the track axis.
#include <gtest/gtest.h>

#include "map_scoring.hpp"

using namespace sonarfusion;
using namespace sonarfusion::eval;

namespace {
// Seabed iz 80..84, a confirmed 10 x 6 x 10 box on it, and beside the track
// (iy 70..73, all x) an apparent seabed 0.5 m higher, as beside a straight pass.
void buildMap(VoxelMap& m) {
    m.initialiseAt(Eigen::Vector3d(0.0, 0.0, 20.0));
    auto occupy = [&](int ix, int iy, int iz) {
        const std::size_t v = m.linear({ix, iy, iz});
        m.add(v, 3.0f);
        m.setFlag(v, VoxelMap::kPsObserved);
        for (int i = 0; i < 20; ++i) m.addPsEcho(v);
    };
    for (int iy = 0; iy < 100; ++iy)
        for (int ix = 0; ix < 100; ++ix)
            for (int iz = 80; iz <= 84; ++iz) occupy(ix, iy, iz);
    for (int iz = 70; iz < 80; ++iz)
        for (int iy = 45; iy <= 50; ++iy)
            for (int ix = 40; ix < 50; ++ix) occupy(ix, iy, iz);
    for (int iy = 70; iy <= 73; ++iy)
        for (int ix = 0; ix < 100; ++ix)
            for (int iz = 75; iz < 80; ++iz) occupy(ix, iy, iz);
}
}  // namespace

TEST(MapScoring, SegmentsWithTheMapperConfigAndTheTrackAxis) {
    VoxelMap m{MapConfig{}};
    buildMap(m);
    // This map's band beside the track holds PS echoes too, so the seabed must
    // come from the occupied surface here (segmentation.seabed_from_ps_echoes
    // false), the rule whose track-axis plumbing this test checks.
    MapperConfig cfg;
    cfg.segmentation.seabed_from_ps_echoes = false;
    const Prediction square = segmentMap(m, Variant::Fused, cfg, Eigen::Vector2d::Zero());  // no track axis
    EXPECT_EQ(square.stats.objects, 2);                             // box + the band beside the track

    const Prediction along = segmentMap(m, Variant::Fused, cfg, Eigen::Vector2d(1.0, 0.0));
    EXPECT_EQ(along.stats.objects, 1);
    EXPECT_TRUE(along.object[m.linear({45, 47, 75})]);
    EXPECT_FALSE(along.object[m.linear({45, 71, 77})]);

    // The config's segmentation settings are used, the variant preset still applies.
    cfg.segmentation.min_object_voxels = 1000;
    cfg.update.require_ps_observation = true;
    EXPECT_EQ(segmentMap(m, Variant::Fused, cfg, Eigen::Vector2d(1.0, 0.0)).stats.objects, 0);
    cfg.segmentation.min_object_voxels = 10;
    EXPECT_EQ(segmentMap(m, Variant::FlsOnly, cfg, Eigen::Vector2d(1.0, 0.0)).stats.unconfirmed_voxels, 0);
}

// Each visible voxel that no predicted voxel recalls is put in one class by the
// map's state at it; recalled ones (a predicted voxel within one voxel) in none.
TEST(MapScoring, MissedVisibleVoxelsAreClassedByTheMapsStateAtThem) {
    VoxelMap m{MapConfig{}};
    m.initialiseAt(Eigen::Vector3d(0.0, 0.0, 20.0));
    const GridSpec grid = GridSpec::of(m);
    Prediction p;
    p.object.assign(m.size(), 0);
    p.occupied.assign(m.size(), 0);
    VoxelMask visible(m.size(), 0);
    auto at = [&](int x) { return m.linear({x, 50, 50}); };
    // Five missed surface voxels, ten voxels apart, one per class.
    m.add(at(10), -2.0f);  // carved, though it holds a PS echo
    m.setFlag(at(10), VoxelMap::kPsObserved);
    m.addPsEcho(at(10));
    m.add(at(20), -2.0f);  // carved
    m.add(at(30), 0.5f);   // seen once or twice, not occupied
    for (int x : {40, 50}) {
        m.add(at(x), 3.0f);  // occupied but in no object
        p.occupied[at(x)] = 1;
    }
    m.setFlag(at(40), VoxelMap::kPsObserved);
    // A recalled one: its neighbour is predicted.
    p.object[at(61)] = 1;
    for (int x : {10, 20, 30, 40, 50, 60}) visible[at(x)] = 1;
    const MissedVisible missed = missedVisible(grid, m, p, visible);
    EXPECT_EQ(missed.free_with_ps_echoes, 1u);
    EXPECT_EQ(missed.free, 1u);
    EXPECT_EQ(missed.not_occupied, 1u);
    EXPECT_EQ(missed.occupied_ps_observed, 1u);
    EXPECT_EQ(missed.occupied_outside_ps, 1u);
    EXPECT_EQ(missed.total(), 5u);
}
