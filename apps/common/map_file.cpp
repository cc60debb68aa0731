#include "map_file.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace sonarfusion {

namespace {
constexpr char kMagic[8] = {'S', 'F', 'M', 'A', 'P', '0', '0', '1'};

[[noreturn]] void fail(const std::string& path, const std::string& why) {
    throw std::runtime_error("map file " + path + ": " + why);
}

template <class T>
void put(std::ofstream& f, const T& v) {
    f.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <class T>
void get(std::ifstream& f, T& v, const std::string& path) {
    if (!f.read(reinterpret_cast<char*>(&v), sizeof(T))) fail(path, "truncated header");
}

// Write to path.tmp, flush, then rename: readers never see half a file.
template <class Writer>
void writeAtomically(const std::string& path, Writer&& write) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) fail(path, "cannot open " + tmp + " for writing");
        write(f);
        f.flush();
        if (!f) fail(path, "write failed");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(path, std::string("rename failed: ") + std::strerror(errno));
}
}  // namespace

void saveMap(const std::string& path, const VoxelMap& map, const std::string& variant) {
    writeAtomically(path, [&](std::ofstream& f) {
        f.write(kMagic, sizeof(kMagic));
        put(f, static_cast<int32_t>(map.nx()));
        put(f, static_cast<int32_t>(map.ny()));
        put(f, static_cast<int32_t>(map.nz()));
        put(f, map.resolution());
        for (int i = 0; i < 3; ++i) put(f, map.origin()[i]);
        put(f, map.clampMin());
        put(f, map.clampMax());
        put(f, static_cast<uint8_t>(map.initialised() ? 1 : 0));
        put(f, static_cast<uint32_t>(variant.size()));
        f.write(variant.data(), static_cast<std::streamsize>(variant.size()));
        f.write(reinterpret_cast<const char*>(map.logOddsData().data()),
                static_cast<std::streamsize>(map.size() * sizeof(float)));
        f.write(reinterpret_cast<const char*>(map.flagsData().data()), static_cast<std::streamsize>(map.size()));
    });
}

namespace {
MapFileHeader readHeader(std::ifstream& f, const std::string& path) {
    char magic[8];
    if (!f.read(magic, sizeof(magic)) || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
        fail(path, "not a sonarfusion map (bad magic)");
    MapFileHeader h;
    int32_t n[3];
    for (int32_t& v : n) get(f, v, path);
    h.nx = n[0], h.ny = n[1], h.nz = n[2];
    get(f, h.resolution, path);
    for (double& o : h.origin) get(f, o, path);
    get(f, h.clamp_min, path);
    get(f, h.clamp_max, path);
    uint8_t init = 0;
    get(f, init, path);
    h.initialised = init != 0;
    uint32_t len = 0;
    get(f, len, path);
    if (len > 64) fail(path, "variant name too long");
    h.variant.resize(len);
    if (len && !f.read(h.variant.data(), len)) fail(path, "truncated header");
    if (h.nx <= 0 || h.ny <= 0 || h.nz <= 0 || h.nx > 4096 || h.ny > 4096 || h.nz > 4096)
        fail(path, "bad dimensions");
    if (!(h.resolution > 0.0) || !std::isfinite(h.resolution)) fail(path, "bad resolution");
    return h;
}
}  // namespace

MapFileHeader readMapHeader(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "cannot open");
    return readHeader(f, path);
}

MapConfig mapConfigOf(const MapFileHeader& h) {
    MapConfig c;
    c.nx = h.nx, c.ny = h.ny, c.nz = h.nz;
    c.resolution = h.resolution;
    c.clamp_min = h.clamp_min, c.clamp_max = h.clamp_max;
    return c;
}

MapFileHeader loadMap(const std::string& path, VoxelMap& map) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "cannot open");
    const MapFileHeader h = readHeader(f, path);
    if (h.nx != map.nx() || h.ny != map.ny() || h.nz != map.nz()) fail(path, "dimensions differ from the map");
    std::vector<float> l(map.size());
    std::vector<uint8_t> flags(map.size());
    if (!f.read(reinterpret_cast<char*>(l.data()), static_cast<std::streamsize>(l.size() * sizeof(float))) ||
        !f.read(reinterpret_cast<char*>(flags.data()), static_cast<std::streamsize>(flags.size())))
        fail(path, "truncated voxel data");
    map.initialiseAt(Eigen::Vector3d(h.origin[0], h.origin[1], h.origin[2]) + 0.5 * map.extent());
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (!std::isfinite(l[i])) fail(path, "non-finite log-odds at voxel " + std::to_string(i));
        map.setLogOdds(i, l[i]);
        map.setFlags(i, flags[i]);
    }
    return h;
}

void savePly(const std::string& path, const VoxelMap& map, double probability_threshold,
             const std::vector<int32_t>* only_labelled) {
    const float l_thr = static_cast<float>(logOddsFromProbability(probability_threshold));
    std::vector<std::size_t> keep;
    for (std::size_t i = 0; i < map.size(); ++i) {
        if (map.logOdds(i) <= l_thr) continue;
        if (only_labelled && (*only_labelled)[i] == 0) continue;
        keep.push_back(i);
    }
    writeAtomically(path, [&](std::ofstream& f) {
        f << "ply\nformat ascii 1.0\ncomment sonarfusion occupied voxel centres, NED metres\n"
          << "element vertex " << keep.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
          << "property float occupancy\nproperty uchar ps_observed\nend_header\n";
        char line[160];
        for (std::size_t i : keep) {
            const Eigen::Vector3d c = map.centreOf(map.fromLinear(i));
            std::snprintf(line, sizeof(line), "%.3f %.3f %.3f %.4f %d\n", c.x(), c.y(), c.z(), map.occupancy(i),
                          map.psObserved(i) ? 1 : 0);
            f << line;
        }
    });
}

}  // namespace sonarfusion
