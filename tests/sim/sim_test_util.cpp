#include "sim_test_util.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "lcm_output.hpp"
#include "simulator.hpp"

namespace sonarfusion::sim::test {

TempDir::TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "sf-sim-test-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path);
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<LogEvent> readLog(const std::string& path) {
    lcm::LogFile log(path, "r");
    EXPECT_TRUE(log.good()) << path;
    std::vector<LogEvent> events;
    while (const lcm::LogEvent* e = log.readNextEvent())
        events.push_back({e->channel, e->timestamp, std::string(static_cast<const char*>(e->data), e->datalen)});
    return events;
}

std::string simulateToLog(const Scenario& scenario, const std::string& path, int threads) {
    const Simulator sim(scenario);
    LogWriter log(path);
    sim.run(threads, -1, [&](const SequenceOutput& out) { writeSequence(log, scenario.channels, out); });
    return path;
}

TriangleMesh flatPlane(double z, double half) {
    TriangleMesh m;
    m.vertices = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
    m.triangles = {{0, 2, 1}, {0, 3, 2}};  // normal -z: up
    return m;
}

TriangleMesh box(double cx, double cy, double cz, double hx, double hy, double hz) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back({cx + ((i & 1) ? hx : -hx), cy + ((i & 2) ? hy : -hy), cz + ((i & 4) ? hz : -hz)});
    // Faces as outward-facing quads (counter-clockwise seen from outside).
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({uint32_t(q[0]), uint32_t(q[1]), uint32_t(q[2])});
        m.triangles.push_back({uint32_t(q[0]), uint32_t(q[2]), uint32_t(q[3])});
    }
    return m;
}

std::string TinyScenario::yaml() const {
    std::ostringstream y;
    y << "scene:\n  seabed_depth: 20.0\n  meshes:\n";
    std::istringstream lines(meshes);
    for (std::string line; std::getline(lines, line);) y << "    " << line << "\n";
    y << "noise: " << noise << "\n";
    y << "trajectory:\n  passes:\n    - {heading_deg: 0, altitude: " << altitude
      << ", step: " << step << ", sequences: " << sequences << ", start_offset: 0}\n";
    y << extra;
    return y.str();
}

}  // namespace sonarfusion::sim::test
