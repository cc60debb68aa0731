// Ground-truth voxelisation of a unit cube at several offsets, counts derived
// by hand (grid: origin 0, 0.1 m, cube [1,2]^3 + offset):
//  - aligned: the 10^3 cells inside; faces lie on cell boundaries and claim no
//    outer cell. Surface = the outer layer of those: 10^3 - 8^3 = 488.
//  - offset 0.03 on x only: faces x=1.03/2.03 cross cells 10 and 20, so x
//    spans 11 cells, y and z 10: 1100. Surface: the two crossed x slabs (200)
//    plus the inside cells 11..19 touching a y or z face (9 * (100-64) = 324) = 524.
//  - offset 0.03 (or 0.05, faces through cell centres) on all axes: 11^3 =
//    1331, surface 11^3 - 9^3 = 602.
//  - offset (-0.02, 0.07, 0.5): x 11 cells, y 11, z aligned 10: 1210, surface
//    1210 - 9*9*8 = 562.
#include <gtest/gtest.h>

#include <ostream>

#include "eval_test_helpers.hpp"
#include "voxelise.hpp"

namespace sonarfusion::eval {
namespace {

struct CubeCase {
    const char* name;
    Eigen::Vector3d offset;
    std::size_t solid, surface;
};

// gtest prints a parameter in failure messages (and --gtest_list_tests);
// without this it dumps the struct's 48 bytes, the name pointer among them.
void PrintTo(const CubeCase& c, std::ostream* os) {
    *os << c.name << " (offset " << c.offset.x() << ", " << c.offset.y() << ", " << c.offset.z() << ")";
}

class UnitCubeVoxels : public ::testing::TestWithParam<CubeCase> {};

TEST_P(UnitCubeVoxels, CountsMatchHandDerivation) {
    const CubeCase c = GetParam();
    const Eigen::Vector3d lo = Eigen::Vector3d::Ones() + c.offset;
    const std::string path = test::writeBox("unit_cube", lo, lo + Eigen::Vector3d::Ones());
    const MeshVoxels v = voxeliseMesh(loadMesh(path), test::grid(Eigen::Vector3d::Zero(), 30));
    EXPECT_TRUE(v.closed);
    EXPECT_EQ(countSet(v.solid), c.solid);
    EXPECT_EQ(countSet(v.surface), c.surface);
}

INSTANTIATE_TEST_SUITE_P(Offsets, UnitCubeVoxels,
                         ::testing::Values(CubeCase{"Aligned", {0, 0, 0}, 1000, 488},
                                           CubeCase{"X0p03", {0.03, 0, 0}, 1100, 524},
                                           CubeCase{"All0p03", {0.03, 0.03, 0.03}, 1331, 602},
                                           CubeCase{"AllHalfVoxel", {0.05, 0.05, 0.05}, 1331, 602},
                                           CubeCase{"Mixed", {-0.02, 0.07, 0.5}, 1210, 562}),
                         [](const ::testing::TestParamInfo<CubeCase>& i) { return std::string(i.param.name); });

// The same cube in a grid whose origin is not a multiple of the resolution.
TEST(Voxelise, OffsetGridOriginAligned) {
    const Eigen::Vector3d origin(-3.7, 12.3, 18.1);
    const Eigen::Vector3d lo = origin + Eigen::Vector3d(1.0, 1.0, 1.0);
    const std::string path = test::writeBox("unit_cube_far", lo, lo + Eigen::Vector3d::Ones());
    const MeshVoxels v = voxeliseMesh(loadMesh(path), test::grid(origin, 30));
    EXPECT_EQ(countSet(v.solid), 1000u);
    EXPECT_EQ(countSet(v.surface), 488u);
}

// Cells outside the grid are dropped: a cube half outside keeps its inner half.
TEST(Voxelise, ClipsToGrid) {
    const std::string path = test::writeBox("half_out", {-0.5, 0.0, 0.0}, {0.5, 1.0, 1.0});
    const MeshVoxels v = voxeliseMesh(loadMesh(path), test::grid(Eigen::Vector3d::Zero(), 30));
    EXPECT_EQ(countSet(v.solid), 500u);
}

// An open sheet (seabed-like) has no inside: one layer of cells, also when it
// lies exactly on a cell boundary.
TEST(Voxelise, OpenSheetGivesOneLayer) {
    for (double depth : {2.05, 2.0}) {
        const std::string path = test::writeOff("sheet", {{0, 0, depth}, {3, 0, depth}, {3, 3, depth}, {0, 3, depth}},
                                                {{0, 1, 2, 3}});
        const MeshVoxels v = voxeliseMesh(loadMesh(path), test::grid(Eigen::Vector3d::Zero(), 30));
        EXPECT_FALSE(v.closed);
        EXPECT_EQ(countSet(v.solid), 900u) << "depth " << depth;
        EXPECT_EQ(countSet(v.surface), 900u) << "depth " << depth;
    }
}

TEST(Voxelise, UnionOfTwoMeshes) {
    const std::string a = test::writeBox("box_a", {0.5, 0.5, 0.5}, {1.0, 1.0, 1.0});
    const std::string b = test::writeBox("box_b", {2.0, 2.0, 2.0}, {2.3, 2.3, 2.3});
    const MeshVoxels v = voxeliseMeshes({loadMesh(a), loadMesh(b)}, test::grid(Eigen::Vector3d::Zero(), 30));
    EXPECT_EQ(countSet(v.solid), 125u + 27u);
}

TEST(MeshIo, MissingFileThrows) { EXPECT_THROW((void)loadMesh("/nonexistent/mesh.off"), std::runtime_error); }

}  // namespace
}  // namespace sonarfusion::eval
