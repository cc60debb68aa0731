#include <gtest/gtest.h>

#include "sonarfusion/segmentation.hpp"

using namespace sonarfusion;

namespace {
// Seabed: occupied layers iz 80..84 (surface at z = 15 + 8.0 = 23.0 m with origin z 15).
// Box: ix 40..49, iy 45..50, iz 70..79 (1 m tall) resting on it.
void buildScene(VoxelMap& m, bool ps_observed) {
    m.initialiseAt(Eigen::Vector3d(0.0, 0.0, 20.0));
    for (int iy = 0; iy < 100; ++iy)
        for (int ix = 0; ix < 100; ++ix)
            for (int iz = 80; iz <= 84; ++iz) m.add(m.linear({ix, iy, iz}), 3.0f);
    for (int iz = 70; iz < 80; ++iz)
        for (int iy = 45; iy <= 50; ++iy)
            for (int ix = 40; ix < 50; ++ix) {
                const std::size_t v = m.linear({ix, iy, iz});
                m.add(v, 3.0f);
                if (ps_observed) m.setFlag(v, VoxelMap::kPsObserved);
            }
    // A lone speck in the water: too small to be an object.
    m.add(m.linear({10, 10, 30}), 3.0f);
    m.setFlag(m.linear({10, 10, 30}), VoxelMap::kPsObserved);
}
}  // namespace

TEST(Segmentation, FindsTheBoxAboveTheSeabed) {
    VoxelMap m{MapConfig{}};
    buildScene(m, true);
    Segmenter seg(SegmentationConfig{}, true, m);
    const SegmentationStats& st = seg.run(m);
    ASSERT_EQ(st.objects, 1);
    const ObjectInfo& o = seg.objects()[0];
    EXPECT_EQ(o.voxel_count, 10 * 6 * 10);
    EXPECT_NEAR(o.volume_m3, 0.6, 1e-9);
    EXPECT_NEAR(o.height_m, 1.0, 1e-9);
    EXPECT_TRUE(o.bbox_min.isApprox(Eigen::Vector3d(-1.0, -0.5, 22.0)));
    EXPECT_TRUE(o.bbox_max.isApprox(Eigen::Vector3d(0.0, 0.1, 23.0)));
    EXPECT_NEAR(o.centroid.z(), 22.5, 1e-9);
    EXPECT_NEAR(seg.seabedDepth(5, 5), 23.0, 1e-9);
    EXPECT_EQ(seg.objectLabel(m.linear({45, 47, 75})), o.id);
    EXPECT_EQ(seg.objectLabel(m.linear({45, 47, 82})), 0);  // seabed is not object
    EXPECT_EQ(seg.objectLabel(m.linear({10, 10, 30})), 0);  // speck dropped
}

TEST(Segmentation, ObjectDoesNotLiftTheBaselineUnderItself) {
    VoxelMap m{MapConfig{}};
    buildScene(m, true);
    Segmenter seg(SegmentationConfig{}, true, m);
    seg.run(m);
    EXPECT_NEAR(seg.seabedDepth(45, 47), 23.0, 1e-9);
}

TEST(Segmentation, UnconfirmedVoxelsAreNotReportedWhenPsIsRequired) {
    VoxelMap m{MapConfig{}};
    buildScene(m, false);
    Segmenter confirmed(SegmentationConfig{}, true, m);
    EXPECT_EQ(confirmed.run(m).objects, 0);
    EXPECT_EQ(confirmed.stats().unconfirmed_voxels, 600);
    Segmenter any(SegmentationConfig{}, false, m);
    EXPECT_EQ(any.run(m).objects, 1);
}

TEST(Segmentation, RerunsGiveTheSameAnswer) {
    VoxelMap m{MapConfig{}};
    buildScene(m, true);
    Segmenter seg(SegmentationConfig{}, true, m);
    seg.run(m);
    const int first = seg.objects()[0].voxel_count;
    seg.run(m);
    ASSERT_EQ(seg.objects().size(), 1u);
    EXPECT_EQ(seg.objects()[0].voxel_count, first);
}
