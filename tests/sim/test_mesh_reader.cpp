// The one mesh reader (sim/mesh_io.hpp, shared with sf-eval): OBJ face forms,
// binary PLY, and malformed files refused with a message naming the file.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "mesh_io.hpp"
#include "sim_test_util.hpp"

namespace sonarfusion::sim {
namespace {

std::string thrownMessage(const std::string& path) {
    try {
        (void)loadMesh(path);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

TEST(MeshReader, ObjFaceFormsAndNegativeIndices) {
    test::TempDir dir;
    test::writeText(dir.file("q.obj"),
                    "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n"
                    "f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1\n");
    const TriangleMesh m = loadMesh(dir.file("q.obj"));
    ASSERT_EQ(m.vertices.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 3u);  // the quad fan-triangulated, then the triangle
    EXPECT_EQ(m.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (std::array<uint32_t, 3>{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (std::array<uint32_t, 3>{0, 2, 3}));
    EXPECT_EQ(m.vertices[2], Eigen::Vector3d(1, 1, 0));
}

TEST(MeshReader, BinaryPlyReadsTheSameBoxAsObj) {
    test::TempDir dir;
    const TriangleMesh b = test::box(0.25, -0.5, 19.0, 1.0, 0.5, 0.75);
    saveObj(b, dir.file("b.obj"));
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(b.vertices.size()) +
                      "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                      std::to_string(b.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& v : b.vertices) ply.append(reinterpret_cast<const char*>(v.data()), 3 * sizeof(double));
    for (const auto& t : b.triangles) {
        ply.push_back(3);
        for (uint32_t i : t) {
            const int32_t k = static_cast<int32_t>(i);
            ply.append(reinterpret_cast<const char*>(&k), sizeof k);
        }
    }
    std::ofstream(dir.file("b.ply"), std::ios::binary) << ply;
    const TriangleMesh from_obj = loadMesh(dir.file("b.obj"));
    const TriangleMesh from_ply = loadMesh(dir.file("b.ply"));
    ASSERT_EQ(from_ply.vertices.size(), b.vertices.size());
    EXPECT_EQ(from_ply.triangles, b.triangles);
    EXPECT_EQ(from_obj.triangles, b.triangles);
    for (std::size_t i = 0; i < b.vertices.size(); ++i) {
        EXPECT_EQ(from_ply.vertices[i], b.vertices[i]) << i;  // binary doubles: exact
        EXPECT_EQ(from_obj.vertices[i], b.vertices[i]) << i;  // these values print exactly with 9 digits
    }
}

TEST(MeshReader, MalformedFilesAreRefusedNamingTheFile) {
    test::TempDir dir;
    test::writeText(dir.file("line.obj"), "v 0 0 0\nv 1 0 0\nf 1 2\n");
    test::writeText(dir.file("points.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    test::writeText(dir.file("junk.ply"), "not a ply file\n");
    test::writeText(dir.file("box.stl"), "solid x\nendsolid x\n");
    EXPECT_NE(thrownMessage(dir.file("line.obj")).find("line.obj: face 0 has fewer than 3 vertices"), std::string::npos)
        << thrownMessage(dir.file("line.obj"));
    EXPECT_NE(thrownMessage(dir.file("points.obj")).find("points.obj: "), std::string::npos);
    EXPECT_NE(thrownMessage(dir.file("junk.ply")).find("junk.ply: cannot read"), std::string::npos)
        << thrownMessage(dir.file("junk.ply"));
    EXPECT_NE(thrownMessage(dir.file("box.stl")).find("unknown mesh format '.stl'"), std::string::npos);
    EXPECT_NE(thrownMessage(dir.file("missing.off")).find("missing.off: cannot open"), std::string::npos);
}

}  // namespace
}  // namespace sonarfusion::sim
