// The one mesh reader (sim/mesh_io.hpp, shared with sf-eval): OBJ face forms,
// binary PLY, ascii and binary STL, Collada, placing a mesh, and malformed files
// refused with a message naming the file.
#include <gtest/gtest.h>

#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "mesh_io.hpp"
#include "scenario.hpp"
#include "scene.hpp"
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
    test::writeText(dir.file("empty.stl"), "solid x\nendsolid x\n");
    test::writeText(dir.file("box.3ds"), "not read\n");
    EXPECT_NE(thrownMessage(dir.file("line.obj")).find("line.obj: face 0 has fewer than 3 vertices"), std::string::npos)
        << thrownMessage(dir.file("line.obj"));
    EXPECT_NE(thrownMessage(dir.file("points.obj")).find("points.obj: "), std::string::npos);
    EXPECT_NE(thrownMessage(dir.file("junk.ply")).find("junk.ply: cannot read"), std::string::npos)
        << thrownMessage(dir.file("junk.ply"));
    EXPECT_NE(thrownMessage(dir.file("empty.stl")).find("empty.stl: no triangles"), std::string::npos)
        << thrownMessage(dir.file("empty.stl"));
    EXPECT_NE(thrownMessage(dir.file("box.3ds")).find("unknown mesh format '.3ds'"), std::string::npos);
    EXPECT_NE(thrownMessage(dir.file("missing.off")).find("missing.off: cannot open"), std::string::npos);
}

// STL stores every triangle's three corners; the reader merges equal corners
// into shared vertices, so a closed mesh stays closed (the evaluator's
// voxeliser needs that). Ascii, binary, and binary with a header that starts
// with "solid" (as some CAD exporters write) all give the OBJ's box.
std::string asciiStl(const TriangleMesh& m) {
    std::string s = "solid box\n";
    char line[160];
    for (const auto& t : m.triangles) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (uint32_t i : t) {
            std::snprintf(line, sizeof line, "      vertex %.9g %.9g %.9g\n", m.vertices[i].x(), m.vertices[i].y(),
                          m.vertices[i].z());
            s += line;
        }
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid box\n";
}

std::string binaryStl(const TriangleMesh& m, const std::string& header80) {
    std::string s = header80;
    s.resize(80, ' ');
    const uint32_t n = static_cast<uint32_t>(m.triangles.size());
    s.append(reinterpret_cast<const char*>(&n), sizeof n);
    for (const auto& t : m.triangles) {
        const float normal[3] = {0, 0, 0};
        s.append(reinterpret_cast<const char*>(normal), sizeof normal);
        for (uint32_t i : t)
            for (int k = 0; k < 3; ++k) {
                const float c = static_cast<float>(m.vertices[i][k]);
                s.append(reinterpret_cast<const char*>(&c), sizeof c);
            }
        s.append(2, '\0');  // attribute byte count
    }
    return s;
}

// The same triangles over the same corner positions, whatever the vertex order.
void expectSameSurface(const TriangleMesh& a, const TriangleMesh& b, double tol) {
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t f = 0; f < a.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            EXPECT_LT((a.vertices[a.triangles[f][k]] - b.vertices[b.triangles[f][k]]).norm(), tol) << f << " " << k;
}

TEST(MeshReader, StlAsciiAndBinaryReadTheSameClosedBoxAsObj) {
    test::TempDir dir;
    // Binary STL holds floats: coordinates exact in float, so the box is the same.
    const TriangleMesh b = test::box(0.25, -0.5, 19.0, 1.0, 0.5, 0.75);
    test::writeText(dir.file("a.stl"), asciiStl(b));
    std::ofstream(dir.file("b.stl"), std::ios::binary) << binaryStl(b, "binary box");
    std::ofstream(dir.file("c.STL"), std::ios::binary) << binaryStl(b, "solid but binary");
    for (const char* name : {"a.stl", "b.stl", "c.STL"}) {
        SCOPED_TRACE(name);
        const TriangleMesh m = loadMesh(dir.file(name));
        EXPECT_EQ(m.vertices.size(), 8u);  // 36 corners merged into the box's 8
        expectSameSurface(m, b, 1e-12);
    }
}

TEST(MeshReader, PlacementScalesRotatesThenTranslates) {
    test::TempDir dir;
    // A 1 x 2 x 3 mm block modelled y-up at the origin (as many exporters write),
    // stood upright in NED (z down): roll -90 deg takes +y to -z (up).
    TriangleMesh mm;
    mm.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
    mm.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    saveObj(mm, dir.file("t.obj"));
    Placement where;
    where.scale = 0.001;
    where.pose.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    where.pose.translation() = Eigen::Vector3d(5.0, -1.0, 20.0);
    const TriangleMesh m = loadMesh(MeshSource{dir.file("t.obj"), where});
    ASSERT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.triangles, mm.triangles);  // a rotation keeps the winding, so normals stay outward
    EXPECT_LT((m.vertices[0] - Eigen::Vector3d(5.0, -1.0, 20.0)).norm(), 1e-12);
    EXPECT_LT((m.vertices[1] - Eigen::Vector3d(5.001, -1.0, 20.0)).norm(), 1e-12);
    EXPECT_LT((m.vertices[2] - Eigen::Vector3d(5.0, -1.0, 19.998)).norm(), 1e-12);  // 2 mm up
    EXPECT_LT((m.vertices[3] - Eigen::Vector3d(5.0, -0.997, 20.0)).norm(), 1e-12);
    // The default placement leaves the file's vertices bit for bit.
    const TriangleMesh same = loadMesh(MeshSource{dir.file("t.obj")});
    EXPECT_EQ(same.vertices, loadMesh(dir.file("t.obj")).vertices);
}

// The simulator places a scenario's mesh as the evaluator does (the scene
// reads the spec's scale, rpy_deg and position): rays hit the placed binary
// STL where they hit the same box written in the world's metres.
TEST(MeshReader, SceneCastsOnThePlacedMesh) {
    test::TempDir dir;
    // 1.0 (along) x 0.6 (up) x 0.4 (across) m in millimetres about its own origin, y up.
    const TriangleMesh mm = test::box(0, 0, 0, 500, 300, 200);
    std::ofstream(dir.file("block.stl"), std::ios::binary) << binaryStl(mm, "block in mm, y up");
    saveObj(test::flatPlane(20.0), dir.file("plane.obj"));
    const Scenario s = loadScenarioFromString(
        "scene:\n  meshes:\n    - {file: plane.obj, role: seabed}\n"
        "    - {file: block.stl, role: object, scale: 0.001, rpy_deg: [-90, 0, 0], position: [4, 0, 19.7]}\n"
        "trajectory: {passes: [{heading_deg: 0, altitude: 3, step: 0.01, sequences: 2}]}\n",
        dir.path());
    const Scene placed(s.scene);
    const Scene in_place({test::flatPlane(20.0), test::box(4.0, 0.0, 19.7, 0.5, 0.2, 0.3)}, {MeshSpec{}, MeshSpec{}},
                         1.5);
    const Eigen::Vector3f down(0, 0, 1);
    for (const Eigen::Vector3f& origin : {Eigen::Vector3f(4.0f, 0.0f, 10.0f), Eigen::Vector3f(4.45f, 0.15f, 10.0f),
                                         Eigen::Vector3f(4.0f, 0.25f, 10.0f), Eigen::Vector3f(4.55f, 0.0f, 10.0f)}) {
        RayHit a, b;
        placed.cast(origin, &down, 1, 0.0f, 100.0f, &a);
        in_place.cast(origin, &down, 1, 0.0f, 100.0f, &b);
        ASSERT_TRUE(a.hit && b.hit);
        EXPECT_NEAR(a.range, b.range, 1e-4) << origin.transpose();
        EXPECT_EQ(a.mesh, b.mesh) << origin.transpose();
    }
    RayHit top;
    placed.cast(Eigen::Vector3f(4.0f, 0.0f, 10.0f), &down, 1, 0.0f, 100.0f, &top);
    EXPECT_NEAR(top.range, 9.4f, 1e-4);  // the block's top, 0.6 m above the seabed
    EXPECT_EQ(top.mesh, 1u);
}

// Collada (Gazebo / DAVE models) through assimp: the file's <unit> applied, its
// own axes kept (its Z_UP is not turned into y-up), every node's transform
// applied, the parts gathered into one mesh.
TEST(MeshReader, ColladaInMetresInItsOwnAxesWithNodeTransforms) {
    test::TempDir dir;
    const std::string geometry =
        "<geometry id=\"tet\"><mesh><source id=\"p\"><float_array id=\"pa\" count=\"12\">0 0 0 100 0 0 0 200 0 0 0 "
        "300</float_array><technique_common><accessor source=\"#pa\" count=\"4\" stride=\"3\"><param name=\"X\" "
        "type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor>"
        "</technique_common></source><vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/></vertices>"
        "<triangles count=\"4\"><input semantic=\"VERTEX\" source=\"#v\" offset=\"0\"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p>"
        "</triangles></mesh></geometry>";
    test::writeText(dir.file("tet.dae"),
                    "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<COLLADA "
                    "xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
                    "<asset><unit name=\"centimeter\" meter=\"0.01\"/><up_axis>Z_UP</up_axis></asset>\n"
                    "<library_geometries>" + geometry + "</library_geometries>\n"
                    "<library_visual_scenes><visual_scene id=\"s\">"
                    "<node id=\"a\"><instance_geometry url=\"#tet\"/></node>"
                    "<node id=\"b\"><matrix>1 0 0 500 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url=\"#tet\"/></node>"
                    "</visual_scene></library_visual_scenes>\n<scene><instance_visual_scene url=\"#s\"/></scene>\n</COLLADA>\n");
    const TriangleMesh m = loadMesh(dir.file("tet.dae"));
    ASSERT_EQ(m.triangles.size(), 8u);  // two tetrahedra
    ASSERT_EQ(m.vertices.size(), 8u);
    // Every corner of the file, in metres, at each node: (0,0,0) (1,0,0) (0,2,0) (0,0,3), and shifted 5 m in x.
    std::vector<Eigen::Vector3d> expected;
    for (double dx : {0.0, 5.0})
        for (const Eigen::Vector3d& c : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 2, 0),
                                         Eigen::Vector3d(0, 0, 3)})
            expected.push_back(c + Eigen::Vector3d(dx, 0, 0));
    for (const Eigen::Vector3d& e : expected) {
        bool found = false;
        for (const Eigen::Vector3d& v : m.vertices) found = found || (v - e).norm() < 1e-6;
        EXPECT_TRUE(found) << e.transpose();
    }
    for (const auto& t : m.triangles)
        for (uint32_t i : t) EXPECT_LT(i, m.vertices.size());
    test::writeText(dir.file("broken.dae"), "<COLLADA><not closed");
    EXPECT_NE(thrownMessage(dir.file("broken.dae")).find("broken.dae: cannot read"), std::string::npos)
        << thrownMessage(dir.file("broken.dae"));
}

}  // namespace
}  // namespace sonarfusion::sim
