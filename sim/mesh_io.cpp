// CGAL and assimp translation unit: the one mesh reader (library sf_mesh_io).
#include "mesh_io.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iomanip>
#include <limits>
#include <stdexcept>

namespace sonarfusion::mesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::runtime_error("mesh " + path + ": " + what);
}

std::string lowerExtension(const std::string& path) {
    const std::size_t dot = path.find_last_of('.');
    const std::size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

// Collada, the mesh format of Gazebo / DAVE models, through assimp: every
// mesh of the file's scene, each node's transform applied (so a multi-part
// model keeps its layout), in the file's own axes (Collada's up_axis is not
// turned into assimp's y-up) and in metres (its <unit> is applied).
// Faces are triangulated; points and lines are dropped.
TriangleMesh loadSceneFile(const std::string& path) {
    Assimp::Importer importer;
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                       aiProcess_PreTransformVertices | aiProcess_SortByPType);
    if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0)
        fail(path, std::string("cannot read (") + importer.GetErrorString() + ")");
    TriangleMesh m;
    for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
        const aiMesh& part = *scene->mMeshes[k];
        if (m.vertices.size() + part.mNumVertices > std::numeric_limits<uint32_t>::max()) fail(path, "too many vertices");
        const auto base = static_cast<uint32_t>(m.vertices.size());
        for (unsigned v = 0; v < part.mNumVertices; ++v)
            m.vertices.emplace_back(part.mVertices[v].x, part.mVertices[v].y, part.mVertices[v].z);
        for (unsigned f = 0; f < part.mNumFaces; ++f) {
            const aiFace& face = part.mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (unsigned c = 0; c < 3; ++c)
                if (face.mIndices[c] >= part.mNumVertices) fail(path, "mesh " + std::to_string(k) + ": vertex index out of range");
            m.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
    }
    if (m.triangles.empty()) fail(path, "no triangles");
    return m;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path) {
    const std::string ext = lowerExtension(path);
    const bool scene_file = ext == ".dae";
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl" && !scene_file)
        fail(path, "unknown mesh format '" + ext + "' (use .obj, .off, .ply, .stl or .dae)");
    if (!std::ifstream(path, std::ios::binary)) fail(path, "cannot open");
    if (scene_file) return loadSceneFile(path);
    std::vector<Kernel::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    if (!CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false)))
        fail(path, "cannot read (malformed " + ext.substr(1) + ")");
    if (points.size() > std::numeric_limits<uint32_t>::max()) fail(path, "too many vertices");
    TriangleMesh m;
    m.vertices.reserve(points.size());
    for (const auto& p : points) m.vertices.emplace_back(p.x(), p.y(), p.z());
    for (std::size_t f = 0; f < polygons.size(); ++f) {
        const auto& poly = polygons[f];
        if (poly.size() < 3) fail(path, "face " + std::to_string(f) + " has fewer than 3 vertices");
        for (std::size_t i : poly)
            if (i >= points.size()) fail(path, "face " + std::to_string(f) + ": vertex index out of range");
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)
            m.triangles.push_back(
                {static_cast<uint32_t>(poly[0]), static_cast<uint32_t>(poly[k]), static_cast<uint32_t>(poly[k + 1])});
    }
    if (m.triangles.empty()) fail(path, "no triangles");
    return m;
}

TriangleMesh loadMesh(const MeshSource& source) {
    TriangleMesh m = loadMesh(source.path);
    applyPlacement(m, source.placement);
    return m;
}

void applyPlacement(TriangleMesh& mesh, const Placement& placement) {
    if (placement.scale == 1.0 && placement.pose.matrix() == Eigen::Matrix4d::Identity()) return;
    for (auto& v : mesh.vertices) v = placement.pose * (placement.scale * v);
}

void saveObj(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    if (!out) fail(path, "cannot write");
    out << std::setprecision(9);
    for (const auto& v : mesh.vertices) out << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

void meshBounds(const TriangleMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const auto& v : mesh.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
}

}  // namespace sonarfusion::mesh
