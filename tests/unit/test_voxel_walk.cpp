// VoxelWalk (voxel_walk.hpp): the Amanatides-Woo walk of the PS carving (Eqs. 12-13).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <vector>

#include "sonarfusion/voxel_map.hpp"
#include "sonarfusion/voxel_walk.hpp"
#include "test_helpers.hpp"

using namespace sonarfusion;

TEST(VoxelWalk, DiagonalRaysVisitFaceConnectedVoxelsOnceAndSkipTheEnd) {
    VoxelMap map = test::originMap();
    std::srand(7);
    for (int trial = 0; trial < 200; ++trial) {
        auto rnd = [] { return 0.5 + 9.0 * std::rand() / RAND_MAX; };
        const Eigen::Vector3d a(rnd(), rnd(), rnd()), b(rnd(), rnd(), rnd());
        std::vector<VoxelIndex> seen;
        double last_t = -1.0;
        const WalkResult r = walkSegment(map, a, b, [&](std::size_t v, double t) {
            seen.push_back(map.fromLinear(v));
            EXPECT_GT(t, last_t);
            EXPECT_LE(t, 1.0);
            last_t = t;
        });
        ASSERT_TRUE(r.end_in_map);
        VoxelIndex va, vb;
        ASSERT_TRUE(map.worldToIndex(a, va));
        ASSERT_TRUE(map.worldToIndex(b, vb));
        if (va == vb) {
            EXPECT_TRUE(seen.empty());
            continue;
        }
        ASSERT_FALSE(seen.empty());
        EXPECT_EQ(seen.front(), va);
        for (const VoxelIndex& v : seen) EXPECT_FALSE(v == vb) << "end voxel must be skipped";
        for (std::size_t i = 1; i < seen.size(); ++i) {
            const int manhattan = std::abs(seen[i].x - seen[i - 1].x) + std::abs(seen[i].y - seen[i - 1].y) +
                                  std::abs(seen[i].z - seen[i - 1].z);
            EXPECT_EQ(manhattan, 1) << "a voxel on the segment was skipped";
        }
        // The last visited voxel is a face neighbour of the end voxel.
        const VoxelIndex& l = seen.back();
        EXPECT_EQ(std::abs(l.x - vb.x) + std::abs(l.y - vb.y) + std::abs(l.z - vb.z), 1);
        std::set<std::size_t> unique;
        for (const VoxelIndex& v : seen) unique.insert(map.linear(v));
        EXPECT_EQ(unique.size(), seen.size());
    }
}

TEST(VoxelWalk, ClipsSegmentsThatStartOutsideTheGrid) {
    VoxelMap map = test::originMap();
    int visited = 0;
    // From 3 m before the grid, along x at y = z = 0.55, to x = 0.45.
    const WalkResult r = walkSegment(map, Eigen::Vector3d(-3.0, 0.55, 0.55), Eigen::Vector3d(0.45, 0.55, 0.55),
                                     [&](std::size_t v, double) {
                                         const VoxelIndex i = map.fromLinear(v);
                                         EXPECT_TRUE(map.contains(i));
                                         EXPECT_EQ(i.y, 5);
                                         ++visited;
                                     });
    EXPECT_TRUE(r.end_in_map);
    EXPECT_EQ(visited, 4);  // voxels 0..3; voxel 4 holds the end
    // Entirely outside: nothing.
    visited = 0;
    walkSegment(map, Eigen::Vector3d(-3, -3, -3), Eigen::Vector3d(-1, 20, -2), [&](std::size_t, double) { ++visited; });
    EXPECT_EQ(visited, 0);
    // Non-finite: nothing, no crash.
    walkSegment(map, Eigen::Vector3d(std::nan(""), 0, 0), Eigen::Vector3d(1, 1, 1), [&](std::size_t, double) { ++visited; });
    EXPECT_EQ(visited, 0);
}
