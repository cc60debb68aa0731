// OctoMap out (issue 14): the .bt written by writeOctomap, loaded back with
// liboctomap, holds exactly our occupied set (and our free set), in ENU.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "map_file.hpp"
#include "octomap_export.hpp"

using namespace sonarfusion;

namespace {

struct Counts {
    std::size_t occupied = 0, free = 0;
};

// Our sets by the documented rule, computed here without the exporter's helper.
Counts ourSets(const VoxelMap& map, double p, std::vector<int>& state) {
    const float thr = static_cast<float>(std::log(p / (1.0 - p)));
    Counts c;
    state.assign(map.size(), 0);  // 0 unknown, 1 free, 2 occupied
    for (std::size_t i = 0; i < map.size(); ++i) {
        const float l = map.logOdds(i);
        if (l == 0.0f) continue;
        state[i] = l > thr ? 2 : 1;
        ++(l > thr ? c.occupied : c.free);
    }
    return c;
}

// Loads `bt` with liboctomap and compares voxel for voxel, then checks the
// tree holds nothing else (the volume of its leaves equals our counts).
void expectSameSets(const VoxelMap& map, double p, const std::string& bt) {
    octomap::OcTree tree(0.05);
    ASSERT_TRUE(tree.readBinary(bt)) << bt;
    ASSERT_DOUBLE_EQ(tree.getResolution(), map.resolution());
    std::vector<int> state;
    const Counts ours = ourSets(map, p, state);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < map.size(); ++i) {
        const VoxelIndex v = map.fromLinear(i);
        const Eigen::Vector3d ned = map.centreOf(v);
        // ENU by hand: x east = NED y, y north = NED x, z up = -NED z.
        const octomap::OcTreeNode* n = tree.search(ned.y(), ned.x(), -ned.z());
        const int theirs = n == nullptr ? 0 : (tree.isNodeOccupied(n) ? 2 : 1);
        if (theirs != state[i] && ++wrong <= 5)
            ADD_FAILURE() << bt << ": voxel " << v.x << "," << v.y << "," << v.z << " ours " << state[i] << " tree "
                          << theirs;
    }
    EXPECT_EQ(wrong, 0u);
    Counts tree_counts;
    for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
        const std::size_t side = std::size_t{1} << (tree.getTreeDepth() - it.getDepth());
        std::size_t& slot = tree.isNodeOccupied(*it) ? tree_counts.occupied : tree_counts.free;
        slot += side * side * side;
    }
    EXPECT_EQ(tree_counts.occupied, ours.occupied) << bt;
    EXPECT_EQ(tree_counts.free, ours.free) << bt;
    EXPECT_GT(ours.occupied, 0u);
}

MapConfig smallGrid() {
    MapConfig c;
    c.nx = 8, c.ny = 6, c.nz = 5;
    c.resolution = 0.1;
    return c;
}

}  // namespace

TEST(OctomapExport, SyntheticMapKeepsOccupiedFreeAndUnknownInEnu) {
    VoxelMap map(smallGrid());
    map.initialiseAt(Eigen::Vector3d(3.0, -2.0, 19.0));
    const double p = 0.7;
    const float thr = static_cast<float>(std::log(p / (1.0 - p)));
    // occupied, free, exactly at the threshold (not occupied), just above it, tiny positive (free).
    map.add(map.linear({1, 2, 3}), 2.0f);
    map.add(map.linear({7, 5, 4}), 4.5f);
    map.add(map.linear({0, 0, 0}), -1.0f);
    map.add(map.linear({2, 2, 2}), thr);
    map.add(map.linear({3, 2, 2}), std::nextafter(thr, 10.0f));
    map.add(map.linear({4, 1, 1}), 0.01f);
    const std::string bt = ::testing::TempDir() + "sf_octomap_synthetic.bt";
    const OctomapExportStats st = writeOctomap(bt, map, p);
    EXPECT_EQ(st.occupied, 3u);
    EXPECT_EQ(st.free, 3u);
    expectSameSets(map, p, bt);

    // One voxel placed by hand: NED centre of (1,2,3) = origin + (1.5, 2.5, 3.5) * 0.1.
    octomap::OcTree tree(0.05);
    ASSERT_TRUE(tree.readBinary(bt));
    const Eigen::Vector3d o = map.origin();
    const double n = o.x() + 0.15, e = o.y() + 0.25, d = o.z() + 0.35;
    const octomap::OcTreeNode* node = tree.search(e, n, -d);
    ASSERT_NE(node, nullptr);
    EXPECT_TRUE(tree.isNodeOccupied(node));
    EXPECT_EQ(tree.search(n, e, d), nullptr);  // not in NED
    std::remove(bt.c_str());
}

TEST(OctomapExport, FailsCleanlyOnUnwritablePath) {
    VoxelMap map(smallGrid());
    map.initialiseAt(Eigen::Vector3d(0, 0, 0));
    map.add(0, 2.0f);
    EXPECT_THROW(writeOctomap("/nonexistent-dir/x.bt", map, 0.7), std::runtime_error);
}

// The reference run's map (ctest fixture): SF_INTEROP_MAP, and the .bt files
// made from it by sf-mapper --octomap-out and sf-map2octomap in SF_INTEROP_BT
// (separated by ':').
TEST(OctomapExport, ReferenceMapFiles) {
    const char* map_path = std::getenv("SF_INTEROP_MAP");
    const char* bts = std::getenv("SF_INTEROP_BT");
    ASSERT_TRUE(map_path && bts) << "set SF_INTEROP_MAP and SF_INTEROP_BT (ctest -L interop does)";
    const MapFileHeader h = readMapHeader(map_path);
    VoxelMap map(mapConfigOf(h));
    loadMap(map_path, map);
    std::stringstream ss(bts);
    std::string bt;
    int n = 0;
    while (std::getline(ss, bt, ':')) {
        if (bt.empty()) continue;
        ++n;
        expectSameSets(map, 0.7, bt);
    }
    EXPECT_EQ(n, 2);
}
