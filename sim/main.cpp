// sf-sim: simulate a scenario into an LCM log or live onto LCM.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>

#include "lcm_output.hpp"
#include "png_export.hpp"
#include "progress.hpp"
#include "scenario.hpp"
#include "simulator.hpp"

namespace sim = sonarfusion::sim;

namespace {

// Keeps what the PNG option needs: the latest FLS frame and the latest sector
// scan of PS pings, and writes the pictures at the requested sequence.
class PngCapture {
public:
    PngCapture(std::string dir, int64_t sequence, std::size_t sweep_pings)
        : dir_(std::move(dir)), sequence_(sequence), sweep_pings_(sweep_pings) {}

    void observe(const sim::SequenceOutput& out) {
        if (done_) return;
        if (out.has_fls) last_fls_ = out.fls;
        sweep_.push_back(out.ps);
        if (sweep_.size() > sweep_pings_) sweep_.pop_front();
        if (out.state.index < sequence_) return;
        std::filesystem::create_directories(dir_);
        const std::string tag = std::to_string(out.state.index);
        if (last_fls_) {
            sim::writeFlsPolarPng(*last_fls_, dir_ + "/fls_polar_" + tag + ".png");
            sim::writeFlsFanPng(*last_fls_, dir_ + "/fls_fan_" + tag + ".png");
        }
        sim::writePsSweepPng({sweep_.begin(), sweep_.end()}, dir_ + "/ps_sweep_" + tag + ".png");
        sim::writePsPingPng(out.ps, dir_ + "/ps_ping_" + tag + ".png");
        done_ = true;
    }
    [[nodiscard]] bool done() const { return done_; }

private:
    std::string dir_;
    int64_t sequence_;
    std::size_t sweep_pings_;
    std::optional<sonarfusion::fls_image_t> last_fls_;
    std::deque<sonarfusion::ps_ping_t> sweep_;
    bool done_ = false;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"sf-sim: ray-traced FLS + profiling-sonar simulator (writes NAV, FLS, PS and, with NAV errors or "
                 "motion, NAV_TRUTH on LCM)"};
    std::string scenario_path, log_path, lcm_url, png_dir;
    bool publish = false, quiet = false;
    double rate = 1.0;
    int threads = 0;
    int64_t sequences = -1, png_seq = 0;
    std::optional<uint64_t> seed;
    std::string nav_channel, fls_channel, ps_channel, truth_channel;
    app.add_option("--scenario", scenario_path, "scenario YAML (docs/scenario-format.md)")->required();
    auto* log_opt = app.add_option("--log", log_path, "write an LCM log file");
    auto* pub_opt = app.add_flag("--publish", publish, "publish live on LCM");
    log_opt->excludes(pub_opt);
    app.add_option("--rate", rate, "live pace: 1 = real time, N = N times faster, 0 = as fast as possible")
        ->check(CLI::NonNegativeNumber)
        ->needs(pub_opt);
    app.add_option("--lcm-url", lcm_url, "LCM URL for --publish (default: LCM_DEFAULT_URL or udpm)");
    app.add_option("--threads", threads, "worker threads (0 = all cores)")->check(CLI::NonNegativeNumber);
    app.add_option("--seed", seed, "override the scenario's random seed");
    app.add_option("--sequences", sequences, "simulate only the first N sequences")->check(CLI::PositiveNumber);
    app.add_option("--png-dir", png_dir, "write PNGs of an FLS frame and the PS sector scan here");
    app.add_option("--png-seq", png_seq, "sequence to picture (the FLS frame is the latest at or before it)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--nav-channel", nav_channel, "override the NAV channel name");
    app.add_option("--fls-channel", fls_channel, "override the FLS channel name");
    app.add_option("--ps-channel", ps_channel, "override the PS channel name");
    app.add_option("--nav-truth-channel", truth_channel,
                   "override the NAV_TRUTH channel name (the true pose, sent when the scenario has NAV errors or motion)");
    app.add_flag("-q,--quiet", quiet, "no progress bar");
    CLI11_PARSE(app, argc, argv);

    if (log_path.empty() && !publish && png_dir.empty()) {
        std::fprintf(stderr, "sf-sim: give --log FILE or --publish (or --png-dir DIR)\n");
        return 2;
    }

    sim::Scenario scenario;
    try {
        scenario = sim::loadScenario(scenario_path);
    } catch (const sim::ScenarioError& e) {
        std::fprintf(stderr, "sf-sim: %s: %s\n", scenario_path.c_str(), e.what());
        return 2;
    }
    if (seed) scenario.seed = *seed;
    if (!nav_channel.empty()) scenario.channels.nav = nav_channel;
    if (!fls_channel.empty()) scenario.channels.fls = fls_channel;
    if (!ps_channel.empty()) scenario.channels.ps = ps_channel;
    if (!truth_channel.empty()) scenario.channels.nav_truth = truth_channel;

    try {
        const sim::Simulator simulator(scenario);
        std::unique_ptr<sim::MessageWriter> writer;
        sim::LivePublisher* live = nullptr;
        if (!log_path.empty()) {
            writer = std::make_unique<sim::LogWriter>(log_path);
        } else if (publish) {
            auto p = std::make_unique<sim::LivePublisher>(lcm_url, rate);
            live = p.get();
            writer = std::move(p);
        }
        const int64_t total = sequences < 0 ? static_cast<int64_t>(simulator.sequences().size())
                                            : std::min<int64_t>(sequences, simulator.sequences().size());
        const double span = scenario.ps.head_max - scenario.ps.head_min;
        std::optional<PngCapture> png;
        if (!png_dir.empty())
            png.emplace(png_dir, png_seq, static_cast<std::size_t>(2 * std::llround(span / scenario.ps_sim.head_step) + 1));

        sim::ProgressBar progress(total, !quiet);
        int64_t done = 0, fls_frames = 0;
        simulator.run(threads, total, [&](const sim::SequenceOutput& out) {
            if (writer) sim::writeSequence(*writer, scenario.channels, out);
            if (png) png->observe(out);
            fls_frames += out.has_fls ? 1 : 0;
            progress.update(++done);
        });
        progress.finish();
        if (!quiet)
            std::fprintf(stderr, "sf-sim: %lld sequences (%lld FLS frames) in %.2f s\n", static_cast<long long>(done),
                         static_cast<long long>(fls_frames), progress.elapsed());
        if (live && live->failures() > 0)
            std::fprintf(stderr, "sf-sim: warning: LCM refused %lld messages\n", static_cast<long long>(live->failures()));
        if (png && !png->done()) {
            std::fprintf(stderr, "sf-sim: --png-seq %lld is past the last simulated sequence\n",
                         static_cast<long long>(png_seq));
            return 2;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sf-sim: %s\n", e.what());
        return 1;
    }
    return 0;
}
