// The map file loader against damaged and hostile files: every bad file is a
// std::runtime_error naming the file and the reason, never a crash, never an
// allocation larger than the file, and a failed load leaves the map as it was.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "map_file.hpp"
#include "temp_dir.hpp"

using namespace sonarfusion;

namespace {
// Each test's own folder (temp_dir.hpp).
class TempDir : public test::TempDir {
public:
    TempDir() : test::TempDir("sf-mapfile-test") {}
};

std::vector<uint8_t> readBytes(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void writeBytes(const std::string& p, const std::vector<uint8_t>& b) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}
template <class T>
void poke(std::vector<uint8_t>& b, std::size_t off, T v) {
    std::memcpy(b.data() + off, &v, sizeof v);
}

MapConfig smallConfig() {
    MapConfig c;
    c.nx = 6, c.ny = 5, c.nz = 4;
    c.resolution = 0.25;
    return c;
}

// Field offsets (docs/map-format.md).
constexpr std::size_t kNx = 8, kNy = 12, kNz = 16, kRes = 20, kOrigin = 28, kClampMin = 52, kClampMax = 56,
                      kInit = 60, kVariantLen = 61, kVariant = 65;

struct Fixture {
    TempDir dir;
    std::string path = dir.file("m.map");
    std::vector<uint8_t> bytes;
    Fixture() {
        VoxelMap m(smallConfig());
        m.initialiseAt(Eigen::Vector3d(1.0, -2.0, 15.0));
        for (std::size_t i = 0; i < m.size(); ++i) {
            m.setLogOdds(i, static_cast<float>(static_cast<int>(i % 11) - 5) * 0.7f);
            m.setFlags(i, static_cast<uint8_t>(i * 7));
            m.setFlsAboveSeabedVotes(i, static_cast<uint8_t>(i * 13));
            m.setPsCrossings(i, static_cast<uint8_t>(i * 5 + 1));
        }
        saveMap(path, m, "fused");
        bytes = readBytes(path);
    }
    // The error loading `b` gives (readMapHeader, then loadMap into a map of
    // the right size), or "" if it loads.
    std::string errorOf(const std::vector<uint8_t>& b) {
        const std::string p = dir.file("bad.map");
        writeBytes(p, b);
        try {
            const MapFileHeader h = readMapHeader(p);
            VoxelMap m(mapConfigOf(h));
            loadMap(p, m);
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(p), std::string::npos) << "the message names the file: " << what;
            return what.empty() ? "?" : what;
        }
        return "";
    }
};
}  // namespace

TEST(MapFile, SavesAndLoadsExactly) {
    Fixture fx;
    ASSERT_EQ(fx.bytes.size(), kVariant + 5 + 6 * 5 * 4 * 7u);
    const MapFileHeader h = readMapHeader(fx.path);
    EXPECT_EQ(h.variant, "fused");
    EXPECT_TRUE(h.initialised);
    VoxelMap m(mapConfigOf(h));
    loadMap(fx.path, m);
    const std::string again = fx.dir.file("again.map");
    saveMap(again, m, h.variant);
    EXPECT_EQ(readBytes(again), fx.bytes);
}

// Version 2 (SFMAP002) files have no PS crossing counts: they still load,
// with everything else as saved and every crossing count zero.
TEST(MapFile, AVersionTwoFileLoadsWithoutPsCrossings) {
    Fixture fx;
    ASSERT_EQ(std::string(fx.bytes.begin(), fx.bytes.begin() + 8), "SFMAP003");
    const std::size_t n = 6 * 5 * 4;
    std::vector<uint8_t> v2(fx.bytes.begin(), fx.bytes.end() - static_cast<std::ptrdiff_t>(n));
    v2[7] = '2';
    const std::string p = fx.dir.file("v2.map");
    writeBytes(p, v2);
    const MapFileHeader h = readMapHeader(p);
    EXPECT_EQ(h.version, 2);
    VoxelMap m(mapConfigOf(h));
    loadMap(p, m);
    VoxelMap want(mapConfigOf(h));
    loadMap(fx.path, want);
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(m.logOdds(i), want.logOdds(i));
        ASSERT_EQ(m.flags(i), want.flags(i));
        ASSERT_EQ(m.flsAboveSeabedVotes(i), want.flsAboveSeabedVotes(i));
        ASSERT_EQ(m.psCrossings(i), 0);
        ASSERT_EQ(want.psCrossings(i), static_cast<uint8_t>(i * 5 + 1));
    }
    // A version 2 file with the version 3 size is refused, not misread; so is
    // a version the reader does not know.
    std::vector<uint8_t> v2_long = fx.bytes;
    v2_long[7] = '2';
    EXPECT_NE(fx.errorOf(v2_long).find("trailing"), std::string::npos);
    std::vector<uint8_t> v4 = fx.bytes;
    v4[7] = '4';
    EXPECT_NE(fx.errorOf(v4).find("bad magic"), std::string::npos);
}

// Version 1 (SFMAP001) files have no above-seabed vote counts: they still
// load, with log-odds and flags as saved and every count zero.
TEST(MapFile, AVersionOneFileLoadsWithoutAboveSeabedVotes) {
    Fixture fx;
    const std::size_t n = 6 * 5 * 4;
    std::vector<uint8_t> v1(fx.bytes.begin(), fx.bytes.end() - static_cast<std::ptrdiff_t>(2 * n));
    v1[7] = '1';
    const std::string p = fx.dir.file("v1.map");
    writeBytes(p, v1);
    const MapFileHeader h = readMapHeader(p);
    EXPECT_EQ(h.version, 1);
    VoxelMap m(mapConfigOf(h));
    loadMap(p, m);
    VoxelMap want(mapConfigOf(h));
    loadMap(fx.path, want);
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(m.logOdds(i), want.logOdds(i));
        ASSERT_EQ(m.flags(i), want.flags(i));
        ASSERT_EQ(m.flsAboveSeabedVotes(i), 0);
        ASSERT_EQ(want.flsAboveSeabedVotes(i), static_cast<uint8_t>(i * 13));
    }
    // A version 1 file with the version 2 size is refused, not misread.
    std::vector<uint8_t> v1_long(fx.bytes.begin(), fx.bytes.end() - static_cast<std::ptrdiff_t>(n));
    v1_long[7] = '1';
    EXPECT_NE(fx.errorOf(v1_long).find("trailing"), std::string::npos);
}

TEST(MapFile, EveryTruncationIsAClearError) {
    Fixture fx;
    for (std::size_t n = 0; n < fx.bytes.size(); ++n) {
        const std::vector<uint8_t> b(fx.bytes.begin(), fx.bytes.begin() + static_cast<std::ptrdiff_t>(n));
        EXPECT_NE(fx.errorOf(b), "") << "cut to " << n << " bytes";
    }
    std::vector<uint8_t> longer = fx.bytes;
    longer.push_back(0);
    EXPECT_NE(fx.errorOf(longer).find("trailing"), std::string::npos);
}

TEST(MapFile, HostileHeadersAreRefusedBeforeAnyAllocation) {
    Fixture fx;
    auto with = [&](auto mutate) {
        std::vector<uint8_t> b = fx.bytes;
        mutate(b);
        return fx.errorOf(b);
    };
    // 4096^3 voxels claimed by a file of a few hundred bytes: refused from the
    // header and the file size alone (the reader would otherwise allocate 343 GB).
    EXPECT_NE(with([](auto& b) { poke<int32_t>(b, kNx, 4096), poke<int32_t>(b, kNy, 4096), poke<int32_t>(b, kNz, 4096); })
                  .find("truncated voxel data"),
              std::string::npos);
    for (int32_t n : {0, -1, 4097, std::numeric_limits<int32_t>::min()})
        EXPECT_NE(with([&](auto& b) { poke<int32_t>(b, kNy, n); }).find("bad dimensions"), std::string::npos) << n;
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (double r : {0.0, -0.1, nan, inf})
        EXPECT_NE(with([&](auto& b) { poke<double>(b, kRes, r); }).find("bad resolution"), std::string::npos) << r;
    EXPECT_NE(with([&](auto& b) { poke<double>(b, kRes, 1e308); }).find("bad origin"), std::string::npos);
    for (double o : {nan, inf, -inf})
        EXPECT_NE(with([&](auto& b) { poke<double>(b, kOrigin + 8, o); }).find("bad origin"), std::string::npos) << o;
    const float fnan = std::numeric_limits<float>::quiet_NaN();
    for (float c : {0.0f, 1.0f, fnan, -std::numeric_limits<float>::infinity()})
        EXPECT_NE(with([&](auto& b) { poke<float>(b, kClampMin, c); }).find("clamp"), std::string::npos) << c;
    EXPECT_NE(with([&](auto& b) { poke<float>(b, kClampMax, -1.0f); }).find("clamp"), std::string::npos);
    EXPECT_NE(with([](auto& b) { b[kInit] = 2; }).find("initialised"), std::string::npos);
    for (uint32_t len : {65u, 0xffffffffu})
        EXPECT_NE(with([&](auto& b) { poke<uint32_t>(b, kVariantLen, len); }).find("variant name too long"),
                  std::string::npos);
    EXPECT_NE(with([](auto& b) { b[kVariant] = 0x01; }).find("printable"), std::string::npos);
    EXPECT_NE(with([](auto& b) { b[0] = 'X'; }).find("bad magic"), std::string::npos);
    // A variant length one shorter: every later field shifts, the size no longer matches.
    EXPECT_NE(with([](auto& b) { poke<uint32_t>(b, kVariantLen, 4); }), "");
}

TEST(MapFile, NonFiniteVoxelLeavesTheMapUntouched) {
    Fixture fx;
    std::vector<uint8_t> b = fx.bytes;
    poke<float>(b, kVariant + 5 + 4 * 17, std::numeric_limits<float>::quiet_NaN());
    const std::string p = fx.dir.file("nan.map");
    writeBytes(p, b);
    VoxelMap m(smallConfig());
    EXPECT_THROW(loadMap(p, m), std::runtime_error);
    EXPECT_FALSE(m.initialised());
    for (std::size_t i = 0; i < m.size(); ++i) ASSERT_EQ(m.logOdds(i), 0.0f);
}

TEST(MapFile, NotAFile) {
    Fixture fx;
    EXPECT_THROW((void)readMapHeader(fx.dir.file("missing.map")), std::runtime_error);
    try {
        (void)readMapHeader(fx.dir.file(""));
        FAIL() << "a directory loaded";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
    VoxelMap wrong(MapConfig{});
    EXPECT_THROW(loadMap(fx.path, wrong), std::runtime_error);  // dimensions differ
}
