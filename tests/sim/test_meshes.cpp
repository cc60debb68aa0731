// Mesh readers, and the reference meshes: closed and consistently oriented
// (the evaluator voxelises them with an inside test).
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "mesh_io.hpp"
#include "sim_test_util.hpp"

namespace sonarfusion::sim {
namespace {

double signedVolume(const TriangleMesh& m) {
    double v = 0.0;
    for (const auto& t : m.triangles) {
        const auto& a = m.vertices[t[0]];
        const auto& b = m.vertices[t[1]];
        const auto& c = m.vertices[t[2]];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6.0;
}

// Closed and consistently oriented: every directed edge once, its reverse once.
bool closedAndOriented(const TriangleMesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : edges) {
        const auto rev = edges.find({e.second, e.first});
        if (n != 1 || rev == edges.end() || rev->second != 1) return false;
    }
    return true;
}

TEST(Meshes, ReferenceMeshesAreClosedWithOutwardNormals) {
    const std::string dir = std::string(SF_SOURCE_DIR) + "/scenarios/meshes/";
    const std::map<std::string, double> volumes = {
        {"seabed.obj", 360.0}, {"slope_box_90.obj", 2.4}, {"slope_box_60.obj", 1.2 * (2.0 + 2.0 - 2.0 / std::sqrt(3.0)) / 2.0}};
    for (const auto& [name, volume] : volumes) {
        const TriangleMesh m = loadMesh(dir + name);
        EXPECT_TRUE(closedAndOriented(m)) << name;
        EXPECT_NEAR(signedVolume(m), volume, 0.05 * volume) << name;  // > 0: outward normals
    }
}

TEST(Meshes, SlopeBoxHasPaperDimensions) {
    const TriangleMesh m = loadMesh(std::string(SF_SOURCE_DIR) + "/scenarios/meshes/slope_box_60.obj");
    double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
    for (const auto& v : m.vertices)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    EXPECT_NEAR(hi[0] - lo[0], 2.0, 1e-4);  // along-track base
    EXPECT_NEAR(hi[1] - lo[1], 1.2, 1e-4);
    EXPECT_NEAR(hi[2] - lo[2], 1.0, 1e-4);
    EXPECT_NEAR(hi[2], 20.0, 1e-4);          // resting on the 20 m seabed
    EXPECT_NEAR(lo[0] + hi[0], 0.0, 1e-4);  // centred at the origin
}

TEST(Meshes, ObjOffPlyReadTheSameBox) {
    test::TempDir dir;
    const TriangleMesh b = test::box(0, 0, 0, 1, 2, 3);
    saveObj(b, dir.file("b.obj"));
    std::string off = "OFF\n# a box\n8 12 0\n", ply = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n"
                                                   "property float y\nproperty float z\nelement face 12\n"
                                                   "property list uchar int vertex_indices\nend_header\n";
    std::string verts, faces;
    for (const auto& v : b.vertices) verts += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
    for (const auto& t : b.triangles) faces += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
    test::writeText(dir.file("b.off"), off + verts + faces);
    test::writeText(dir.file("b.ply"), ply + verts + faces);
    for (const char* name : {"b.obj", "b.off", "b.ply"}) {
        const TriangleMesh m = loadMesh(dir.file(name));
        EXPECT_EQ(m.triangles.size(), 12u) << name;
        EXPECT_TRUE(closedAndOriented(m)) << name;
        EXPECT_NEAR(signedVolume(m), 2 * 4 * 6, 1e-6) << name;
    }
    test::writeText(dir.file("bad.stl"), "solid x\n");
    EXPECT_THROW((void)loadMesh(dir.file("bad.stl")), std::runtime_error);
}

}  // namespace
}  // namespace sonarfusion::sim
