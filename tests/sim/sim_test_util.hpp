// Helpers for the simulator tests: a private temp folder, tiny meshes and a
// small scenario written as YAML (so the tests go through the real loader).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh_io.hpp"
#include "scenario.hpp"

namespace sonarfusion::sim::test {

// A fresh folder under /tmp, removed when the object dies.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] const std::string& path() const { return path_; }
    [[nodiscard]] std::string file(const std::string& name) const { return path_ + "/" + name; }

private:
    std::string path_;
};

void writeText(const std::string& path, const std::string& text);
[[nodiscard]] std::string readBytes(const std::string& path);

// One event of an LCM log, as the tests read it back.
struct LogEvent {
    std::string channel;
    int64_t timestamp;
    std::string data;
};
// Every event of the log at `path` (a failed open is a test failure).
[[nodiscard]] std::vector<LogEvent> readLog(const std::string& path);

// Runs the whole scenario on `threads` workers into an LCM log at `path`
// (as sf-sim --log does); returns path.
std::string simulateToLog(const Scenario& scenario, const std::string& path, int threads);

// Horizontal square at depth z (NED), normal up, half-size `half` metres.
[[nodiscard]] TriangleMesh flatPlane(double z, double half = 30.0);
// Closed axis-aligned box, outward normals.
[[nodiscard]] TriangleMesh box(double cx, double cy, double cz, double hx, double hy, double hz);

// A minimal scenario: the given mesh entries (YAML list items), noise off
// unless `noise` says otherwise, one straight pass north at `altitude` over
// seabed_depth 20 m, starting at the origin.
struct TinyScenario {
    std::string meshes;  // e.g. "- {file: plane.obj, role: seabed}\n"
    double altitude = 3.0;
    double step = 0.01;  // m per sequence; 0 holds the vehicle still
    int sequences = 8;
    std::string noise = "{speckle: false, floor: 0}";
    std::string extra;   // appended top-level YAML (fls:, ps:, seed: ...)
    [[nodiscard]] std::string yaml() const;
};

}  // namespace sonarfusion::sim::test
