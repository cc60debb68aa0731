#include "mesh_io.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace sonarfusion::sim {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw std::runtime_error("mesh " + path + ": " + what);
}

void addPolygon(TriangleMesh& m, const std::vector<long>& idx, const std::string& path) {
    if (idx.size() < 3) fail(path, "face with fewer than 3 vertices");
    for (long i : idx)
        if (i < 0 || static_cast<std::size_t>(i) >= m.vertices.size()) fail(path, "face index out of range");
    for (std::size_t k = 1; k + 1 < idx.size(); ++k)
        m.triangles.push_back({static_cast<uint32_t>(idx[0]), static_cast<uint32_t>(idx[k]),
                               static_cast<uint32_t>(idx[k + 1])});
}

TriangleMesh loadObj(std::istream& in, const std::string& path) {
    TriangleMesh m;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            std::array<double, 3> v{};
            if (!(ls >> v[0] >> v[1] >> v[2])) fail(path, "bad vertex line: " + line);
            m.vertices.push_back(v);
        } else if (tag == "f") {
            std::vector<long> idx;
            std::string token;
            while (ls >> token) {
                // "i", "i/t", "i//n", "i/t/n"; negative indices count from the end.
                long i = 0;
                try {
                    i = std::stol(token.substr(0, token.find('/')));
                } catch (const std::logic_error&) {
                    fail(path, "bad face line: " + line);
                }
                idx.push_back(i < 0 ? static_cast<long>(m.vertices.size()) + i : i - 1);
            }
            addPolygon(m, idx, path);
        }
    }
    return m;
}

// Reads the next token that is not part of a '#' comment.
bool nextToken(std::istream& in, std::string& tok) {
    while (in >> tok) {
        if (tok[0] != '#') return true;
        std::string rest;
        std::getline(in, rest);
    }
    return false;
}

TriangleMesh loadOff(std::istream& in, const std::string& path) {
    TriangleMesh m;
    std::string tok;
    if (!nextToken(in, tok) || tok != "OFF") fail(path, "missing OFF header");
    long nv = 0, nf = 0, ne = 0;
    if (!(nextToken(in, tok))) fail(path, "missing counts");
    nv = std::stol(tok);
    in >> nf >> ne;
    if (!in || nv < 0 || nf < 0) fail(path, "bad counts");
    m.vertices.resize(static_cast<std::size_t>(nv));
    for (auto& v : m.vertices)
        if (!(in >> v[0] >> v[1] >> v[2])) fail(path, "truncated vertex list");
    for (long f = 0; f < nf; ++f) {
        long n = 0;
        if (!(in >> n) || n < 3 || n > 1000) fail(path, "bad face " + std::to_string(f));
        std::vector<long> idx(static_cast<std::size_t>(n));
        for (auto& i : idx)
            if (!(in >> i)) fail(path, "truncated face " + std::to_string(f));
        std::getline(in, tok);  // optional colour
        addPolygon(m, idx, path);
    }
    return m;
}

struct PlyProperty {
    std::string type, count_type, name;  // count_type non-empty for lists
};

std::size_t plySize(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

double readBinary(std::istream& in, const std::string& t) {
    unsigned char b[8] = {};
    in.read(reinterpret_cast<char*>(b), static_cast<std::streamsize>(plySize(t)));
    auto as = [&](auto v) {
        std::memcpy(&v, b, sizeof v);
        return static_cast<double>(v);
    };
    if (t == "char" || t == "int8") return as(int8_t{});
    if (t == "uchar" || t == "uint8") return as(uint8_t{});
    if (t == "short" || t == "int16") return as(int16_t{});
    if (t == "ushort" || t == "uint16") return as(uint16_t{});
    if (t == "int" || t == "int32") return as(int32_t{});
    if (t == "uint" || t == "uint32") return as(uint32_t{});
    if (t == "float" || t == "float32") return as(float{});
    return as(double{});
}

TriangleMesh loadPly(std::istream& in, const std::string& path) {
    std::string line;
    std::getline(in, line);
    if (line.rfind("ply", 0) != 0) fail(path, "missing ply header");
    bool binary = false;
    struct Element {
        std::string name;
        long count = 0;
        std::vector<PlyProperty> props;
    };
    std::vector<Element> elements;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string key;
        ls >> key;
        if (key == "format") {
            std::string fmt;
            ls >> fmt;
            if (fmt == "binary_little_endian") binary = true;
            else if (fmt != "ascii") fail(path, "unsupported PLY format " + fmt);
        } else if (key == "element") {
            Element e;
            ls >> e.name >> e.count;
            elements.push_back(e);
        } else if (key == "property" && !elements.empty()) {
            PlyProperty p;
            ls >> p.type;
            if (p.type == "list") ls >> p.count_type >> p.type;
            ls >> p.name;
            if (plySize(p.type) == 0) fail(path, "unknown PLY type " + p.type);
            elements.back().props.push_back(p);
        } else if (key == "end_header") {
            break;
        }
    }
    TriangleMesh m;
    auto value = [&](const std::string& type) {
        if (binary) return readBinary(in, type);
        double v = 0;
        in >> v;
        return v;
    };
    for (const Element& e : elements) {
        for (long i = 0; i < e.count; ++i) {
            std::array<double, 3> v{};
            std::vector<long> face;
            for (const PlyProperty& p : e.props) {
                if (!p.count_type.empty()) {
                    const long n = static_cast<long>(value(p.count_type));
                    if (n < 0 || n > 1000) fail(path, "bad list count in element " + e.name);
                    for (long k = 0; k < n; ++k) {
                        const double x = value(p.type);
                        if (p.name == "vertex_indices" || p.name == "vertex_index") face.push_back(static_cast<long>(x));
                    }
                } else {
                    const double x = value(p.type);
                    if (p.name == "x") v[0] = x;
                    if (p.name == "y") v[1] = x;
                    if (p.name == "z") v[2] = x;
                }
            }
            if (!in) fail(path, "truncated element " + e.name);
            if (e.name == "vertex") m.vertices.push_back(v);
            if (e.name == "face") addPolygon(m, face, path);
        }
    }
    return m;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open");
    std::string ext = path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    TriangleMesh m;
    if (ext == ".obj") m = loadObj(in, path);
    else if (ext == ".off") m = loadOff(in, path);
    else if (ext == ".ply") m = loadPly(in, path);
    else fail(path, "unknown mesh format '" + ext + "' (use .obj, .off or .ply)");
    if (m.triangles.empty()) fail(path, "no triangles");
    return m;
}

void saveObj(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    if (!out) fail(path, "cannot write");
    out << std::setprecision(9);
    for (const auto& v : mesh.vertices) out << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

}  // namespace sonarfusion::sim
