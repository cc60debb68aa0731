// libFuzzer harness for the map file loader (apps/common/map_file.cpp), used
// the way sf-eval uses it: readMapHeader, a VoxelMap of the header's grid,
// loadMap. Any bad file must be a std::runtime_error; anything else (another
// exception, a crash, UB, an allocation over libFuzzer's -malloc_limit_mb) is
// a finding. A file that loads is saved again, and that copy must load and
// save to the same bytes (the origin within a voxel). Build: docs/robustness.md.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_util.hpp"
#include "map_file.hpp"

namespace {
const std::string& scratchDir() {
    // Never destroyed: the atexit handler below runs after static destructors
    // registered later would have.
    static const std::string* dir = [] {
        std::string t = (std::filesystem::temp_directory_path() / "sf-fuzz-map-XXXXXX").string();
        if (!mkdtemp(t.data())) std::abort();
        auto* d = new std::string(t);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratchDir(), ec);
        });
        return d;
    }();
    return *dir;
}

std::vector<char> bytesOf(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string path = sffuzz::asFile(data, size);
    sonarfusion::MapFileHeader h;
    try {
        h = sonarfusion::readMapHeader(path);
    } catch (const std::runtime_error&) {
        return 0;
    }
    sonarfusion::VoxelMap map(sonarfusion::mapConfigOf(h));  // a header that passed must make a valid map
    try {
        sonarfusion::loadMap(path, map);
    } catch (const std::runtime_error&) {
        return 0;
    }
    const std::string a = scratchDir() + "/a.map", b = scratchDir() + "/b.map";
    sonarfusion::saveMap(a, map, h.variant);
    const sonarfusion::MapFileHeader h2 = sonarfusion::readMapHeader(a);
    sonarfusion::VoxelMap again(sonarfusion::mapConfigOf(h2));
    sonarfusion::loadMap(a, again);
    sonarfusion::saveMap(b, again, h2.variant);
    // The second save repeats the first, but for the origin: loading places
    // the grid from its centre (VoxelMap::initialiseAt), which may move it
    // by rounding, never by a voxel.
    std::vector<char> ba = bytesOf(a), bb = bytesOf(b);
    if (ba.size() != bb.size() || ba.size() < 52) __builtin_trap();
    for (int i = 0; i < 3; ++i) {
        double oa, ob;
        std::memcpy(&oa, ba.data() + 28 + 8 * i, 8);
        std::memcpy(&ob, bb.data() + 28 + 8 * i, 8);
        if (!(std::abs(oa - ob) < h.resolution)) __builtin_trap();
    }
    std::fill(ba.begin() + 28, ba.begin() + 52, 0);
    std::fill(bb.begin() + 28, bb.begin() + 52, 0);
    if (ba != bb) __builtin_trap();
    return 0;
}
