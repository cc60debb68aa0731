#include "map_file.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace sonarfusion {

namespace {
// Version 2 adds the above-seabed FLS vote counts after the flags, version 3
// the PS crossing counts after those; older files still load, with the counts
// they lack zero.
constexpr char kMagic[8] = {'S', 'F', 'M', 'A', 'P', '0', '0', '3'};
constexpr char kMagicPrefix[7] = {'S', 'F', 'M', 'A', 'P', '0', '0'};

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
        std::vector<uint8_t> flags(map.size());  // the flag byte, composed from the map's planes
        map.copyFlagBytes(flags.data());
        f.write(reinterpret_cast<const char*>(flags.data()), static_cast<std::streamsize>(flags.size()));
        f.write(reinterpret_cast<const char*>(map.aboveSeabedVotesData().data()),
                static_cast<std::streamsize>(map.size()));
        f.write(reinterpret_cast<const char*>(map.psCrossingsData().data()), static_cast<std::streamsize>(map.size()));
    });
}

namespace {
// Bytes before the voxel data: magic, 3 x int32, 4 x float64, 2 x float32,
// uint8, uint32, then the variant name.
constexpr uint64_t kFixedHeaderBytes = 8 + 3 * 4 + 4 * 8 + 2 * 4 + 1 + 4;
constexpr uint32_t kMaxVariantLen = 64;

// Opens a regular file (not a directory, FIFO or device, which would block or
// fail later with a less clear message) and tells its size.
std::ifstream openMapFile(const std::string& path, uint64_t& size) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) fail(path, "cannot open (no such file)");
    if (!fs::is_regular_file(st)) fail(path, "not a regular file");
    size = fs::file_size(path, ec);
    if (ec) fail(path, "cannot read its size: " + ec.message());
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(path, "cannot open");
    return f;
}

// Every field is checked before anything is sized from it, and the file must
// be exactly as long as the header's grid says: a hostile or damaged header
// can neither make a reader allocate more than the file holds nor leave
// voxels unread.
MapFileHeader readHeader(std::ifstream& f, const std::string& path, uint64_t file_size) {
    char magic[8];
    if (!f.read(magic, sizeof(magic)) || std::memcmp(magic, kMagicPrefix, sizeof(kMagicPrefix)) != 0 ||
        magic[7] < '1' || magic[7] > kMagic[7])
        fail(path, "not a sonarfusion map (bad magic)");
    MapFileHeader h;
    h.version = magic[7] - '0';
    int32_t n[3];
    for (int32_t& v : n) get(f, v, path);
    h.nx = n[0], h.ny = n[1], h.nz = n[2];
    get(f, h.resolution, path);
    for (double& o : h.origin) get(f, o, path);
    get(f, h.clamp_min, path);
    get(f, h.clamp_max, path);
    uint8_t init = 0;
    get(f, init, path);
    uint32_t len = 0;
    get(f, len, path);
    if (len > kMaxVariantLen) fail(path, "variant name too long (" + std::to_string(len) + " bytes, at most 64)");
    h.variant.resize(len);
    if (len && !f.read(h.variant.data(), len)) fail(path, "truncated header");
    if (h.nx <= 0 || h.ny <= 0 || h.nz <= 0 || h.nx > kMaxMapCells || h.ny > kMaxMapCells || h.nz > kMaxMapCells)
        fail(path, "bad dimensions " + std::to_string(h.nx) + " x " + std::to_string(h.ny) + " x " +
                       std::to_string(h.nz) + " (each must be in 1.." + std::to_string(kMaxMapCells) + ")");
    if (!(h.resolution > 0.0) || !std::isfinite(h.resolution)) fail(path, "bad resolution");
    for (int i = 0; i < 3; ++i) {
        const double far = h.origin[i] + n[i] * h.resolution;
        if (!std::isfinite(h.origin[i]) || !std::isfinite(far)) fail(path, "bad origin (not finite, or the grid's far corner is not)");
        // Loading places the grid on the world lattice (origin / resolution
        // rounded): that ratio must be a number a double counts exactly.
        if (!(std::abs(h.origin[i] / h.resolution) <= 0x1p52)) fail(path, "bad origin (more than 2^52 voxels from the world origin)");
    }
    if (!std::isfinite(h.clamp_min) || !std::isfinite(h.clamp_max) || !(h.clamp_min < 0.0f && h.clamp_max > 0.0f))
        fail(path, "bad log-odds clamp (must be finite, clamp_min < 0 < clamp_max)");
    if (init > 1) fail(path, "bad initialised flag " + std::to_string(init) + " (0 or 1)");
    h.initialised = init != 0;
    for (char c : h.variant)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
            fail(path, "variant name is not printable ASCII");
    const uint64_t voxels = static_cast<uint64_t>(h.nx) * static_cast<uint64_t>(h.ny) * static_cast<uint64_t>(h.nz);
    const uint64_t bytes_per_voxel = sizeof(float) + static_cast<uint64_t>(h.version);  // flags, votes, crossings
    const uint64_t expected = kFixedHeaderBytes + len + voxels * bytes_per_voxel;
    if (file_size < expected)
        fail(path, "truncated voxel data (" + std::to_string(file_size) + " bytes; the " + std::to_string(h.nx) + " x " +
                       std::to_string(h.ny) + " x " + std::to_string(h.nz) + " grid needs " + std::to_string(expected) + ")");
    if (file_size > expected)
        fail(path, std::to_string(file_size - expected) + " trailing bytes after the voxel data");
    return h;
}
}  // namespace

MapFileHeader readMapHeader(const std::string& path) {
    uint64_t size = 0;
    std::ifstream f = openMapFile(path, size);
    return readHeader(f, path, size);
}

MapConfig mapConfigOf(const MapFileHeader& h) {
    MapConfig c;
    c.nx = h.nx, c.ny = h.ny, c.nz = h.nz;
    c.resolution = h.resolution;
    c.clamp_min = h.clamp_min, c.clamp_max = h.clamp_max;
    return c;
}

MapFileHeader loadMap(const std::string& path, VoxelMap& map) {
    uint64_t size = 0;
    std::ifstream f = openMapFile(path, size);
    const MapFileHeader h = readHeader(f, path, size);
    if (h.nx != map.nx() || h.ny != map.ny() || h.nz != map.nz()) fail(path, "dimensions differ from the map");
    // The header matched the file's size, so these are as large as the file, no larger.
    std::vector<float> l(map.size());
    std::vector<uint8_t> flags(map.size()), above(map.size(), 0), crossed(map.size(), 0);
    if (!f.read(reinterpret_cast<char*>(l.data()), static_cast<std::streamsize>(l.size() * sizeof(float))) ||
        !f.read(reinterpret_cast<char*>(flags.data()), static_cast<std::streamsize>(flags.size())) ||
        (h.version >= 2 &&
         !f.read(reinterpret_cast<char*>(above.data()), static_cast<std::streamsize>(above.size()))) ||
        (h.version >= 3 &&
         !f.read(reinterpret_cast<char*>(crossed.data()), static_cast<std::streamsize>(crossed.size()))))
        fail(path, "truncated voxel data");
    // Checked before the map is touched: a bad file leaves it as it was.
    for (std::size_t i = 0; i < l.size(); ++i)
        if (!std::isfinite(l[i])) fail(path, "non-finite log-odds at voxel " + std::to_string(i));
    map.initialiseAt(Eigen::Vector3d(h.origin[0], h.origin[1], h.origin[2]) + 0.5 * map.extent());
    for (std::size_t i = 0; i < l.size(); ++i) {
        map.setLogOdds(i, l[i]);
        map.setFlags(i, flags[i]);
        map.setFlsAboveSeabedVotes(i, above[i]);
        map.setPsCrossings(i, crossed[i]);
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
