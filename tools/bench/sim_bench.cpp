// sf-sim-bench: how fast the simulator casts rays, single thread and on all
// cores, plus (--calibrate) the echo levels the receiver gains produce.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <vector>

#include "parallel.hpp"
#include "scenario.hpp"
#include "simulator.hpp"

namespace sim = sonarfusion::sim;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

void benchFls(const sim::Simulator& s, int frames, int threads) {
    const auto& seqs = s.sequences();
    const auto start = Clock::now();
    for (int i = 0; i < frames; ++i) {
        const auto& q = seqs[static_cast<std::size_t>(i * 4) % seqs.size()];
        (void)s.fls().render(q.pose, q.index, threads);
    }
    const double t = seconds(start);
    std::printf("FLS  %2d thread(s): %6.1f frames/s  %7.2f Mrays/s  (%d frames, %lld rays each)\n", threads,
                frames / t, frames * static_cast<double>(s.fls().raysPerFrame()) / t / 1e6, frames,
                static_cast<long long>(s.fls().raysPerFrame()));
}

void benchPs(const sim::Simulator& s, int pings) {
    const auto& seqs = s.sequences();
    const auto start = Clock::now();
    for (int i = 0; i < pings; ++i) {
        const auto& q = seqs[static_cast<std::size_t>(i) % seqs.size()];
        (void)s.ps().ping(q.pose, q.head_angle, q.index);
    }
    const double t = seconds(start);
    std::printf("PS    1 thread   : %6.0f pings/s   %7.2f Mrays/s\n", pings / t,
                pings * static_cast<double>(s.ps().raysPerPing()) / t / 1e6);
}

void calibrate(const sim::Simulator& s, int64_t fls_sequence) {
    const auto& q = s.sequences().at(static_cast<std::size_t>(fls_sequence));
    const sim::FlsImage img = s.fls().render(q.pose, q.index, sim::resolveThreads(0));
    // Echo rows: those whose centre-beam neighbourhood is well above the floor.
    std::vector<int> echo, water;
    for (uint8_t v : img.data) (v > 60 ? echo : water).push_back(v);
    auto stats = [](const char* what, std::vector<int>& v) {
        if (v.empty()) return std::printf("  %-6s none\n", what), void();
        std::sort(v.begin(), v.end());
        const double mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
        const auto above = std::count_if(v.begin(), v.end(), [](int x) { return x > 150; });
        std::printf("  %-6s %7zu px  mean %5.1f  median %3d  p99 %3d  >150: %5.1f%%\n", what, v.size(), mean,
                    v[v.size() / 2], v[v.size() * 99 / 100], 100.0 * above / v.size());
    };
    std::printf("FLS frame at sequence %lld (x = %.2f m):\n", static_cast<long long>(q.index), q.pose.position.x());
    stats("echo", echo);
    stats("water", water);
    std::printf("PS peaks over one sector scan from sequence %lld:\n", static_cast<long long>(fls_sequence));
    for (int i = 0; i < 89; i += 11) {
        const auto& p = s.sequences().at(static_cast<std::size_t>(fls_sequence + i));
        const auto ping = s.ps().ping(p.pose, p.head_angle, p.index);
        const auto peak = std::max_element(ping.begin(), ping.end());
        std::printf("  head %6.1f deg: peak %3d at %.2f m\n", p.head_angle * 180 / M_PI, *peak,
                    s.ps().rangeOfBin(static_cast<int>(peak - ping.begin())));
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"sf-sim-bench: simulator throughput"};
    std::string scenario_path = std::string(SF_SOURCE_DIR) + "/scenarios/slope_box_90.yaml";
    int frames = 40, threads = 0;
    bool full = false;
    int64_t calibrate_at = -1;
    app.add_option("--scenario", scenario_path, "scenario YAML");
    app.add_option("--frames", frames, "FLS frames per measurement")->check(CLI::PositiveNumber);
    app.add_option("--threads", threads, "'all cores' thread count (0 = hardware)");
    app.add_flag("--full", full, "also time the whole scenario (all sequences, no output)");
    app.add_option("--calibrate", calibrate_at, "print echo levels of the FLS frame at this sequence");
    CLI11_PARSE(app, argc, argv);

    const sim::Scenario scenario = sim::loadScenario(scenario_path);
    const auto build = Clock::now();
    const sim::Simulator s(scenario);
    std::printf("scene: %zu triangles, BVH built in %.3f s\n", s.scene().triangleCount(), seconds(build));
    if (calibrate_at >= 0) {
        calibrate(s, calibrate_at);
        return 0;
    }
    const int all = sim::resolveThreads(threads);
    benchFls(s, frames, 1);
    benchFls(s, frames, all);
    benchPs(s, 2000);
    if (full) {
        const auto start = Clock::now();
        int64_t n = 0;
        s.run(all, -1, [&](const sim::SequenceOutput&) { ++n; });
        std::printf("full scenario: %lld sequences in %.2f s on %d thread(s)\n", static_cast<long long>(n),
                    seconds(start), all);
    }
    return 0;
}
