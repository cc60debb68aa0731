// sf-mapper: the mapper daemon. Live on LCM, or offline over an LCM log file
// through the same code path (MapperNode), as fast as possible.
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>
#include <spdlog/spdlog.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <memory>

#include "checkpoint.hpp"
#include "lcm_log_reader.hpp"
#include "map_file.hpp"
#include "mapper_config_yaml.hpp"
#include "mapper_node.hpp"
#include "survey_output.hpp"
#include "sonarfusion/variant.hpp"
#ifdef SF_WITH_OCTOMAP
#include "octomap_export.hpp"
#endif

using namespace sonarfusion;

namespace {
std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

int64_t wallUs() {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

void writeOutputs(MapperNode& node, MapOutputs& outs) {
    node.finish();  // every map still being made is finalised (and written)
    // No map was ever anchored: the empty map, as before survey mode.
    if (node.mapper().counters().map_initialisations == 0 && !outs.map_out.empty())
        writeMapFiles(node.mapper().map(), node.config(), outs.map_out);
    if (outs.write_failures > 0)
        throw std::runtime_error(std::to_string(outs.write_failures) + " finalised map(s) could not be written");
}

// Issue 10, finding 7: a missing or read-only folder is found at start-up, not
// after a whole mission.
void checkWritable(const std::string& path, const char* what) {
    const std::string probe = path + ".tmp";
    FILE* f = std::fopen(probe.c_str(), "wb");
    if (!f) throw std::runtime_error(std::string("cannot write the ") + what + " " + path + ": " + std::strerror(errno));
    std::fclose(f);
    std::remove(probe.c_str());
}

// Peak resident memory of this process (VmHWM), kB; -1 where /proc is missing.
long peakRssKb() {
    FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return -1;
    char line[256];
    long kb = -1;
    while (std::fgets(line, sizeof(line), f))
        if (std::sscanf(line, "VmHWM: %ld kB", &kb) == 1) break;
    std::fclose(f);
    return kb;
}

// The final MAPPER_STATUS as JSON, for scripts (tools/mission merges it into report.json).
void writeStatusJson(MapperNode& node, const std::string& path) {
    const mapper_status_t& s = node.status();
    const std::string tmp = path + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + tmp);
    std::fprintf(f, "{\n  \"state\": \"%s\", \"variant\": \"%s\",\n", s.state.c_str(), s.variant.c_str());
    std::fprintf(f, "  \"map_centre\": [%.4f, %.4f, %.4f],\n", s.map_centre[0], s.map_centre[1], s.map_centre[2]);
    std::fprintf(f, "  \"nav_in\": %lld, \"fls_in\": %lld, \"ps_in\": %lld, \"fls_used\": %lld, \"ps_used\": %lld,\n",
                 static_cast<long long>(s.nav_in), static_cast<long long>(s.fls_in), static_cast<long long>(s.ps_in),
                 static_cast<long long>(s.fls_used), static_cast<long long>(s.ps_used));
    std::fprintf(f, "  \"seq_gaps\": {\"nav\": %lld, \"fls\": %lld, \"ps\": %lld},\n",
                 static_cast<long long>(s.nav_seq_gaps), static_cast<long long>(s.fls_seq_gaps),
                 static_cast<long long>(s.ps_seq_gaps));
    std::fprintf(f, "  \"proc_us\": {\"last\": %.1f, \"max\": %.1f, \"p99\": %.1f, \"budget\": %.1f, \"overruns\": %lld},\n",
                 s.proc_last_us, s.proc_max_us, s.proc_p99_us, s.budget_us, static_cast<long long>(s.budget_overruns));
    std::fprintf(f, "  \"rejected\": {");
    for (int i = 0; i < s.num_reasons; ++i)
        std::fprintf(f, "%s\"%s\": %lld", i ? ", " : "", s.reason_name[i].c_str(), static_cast<long long>(s.reason_count[i]));
    const MapperCounters& c = node.mapper().counters();
    std::fprintf(f, "},\n  \"maps\": {\"anchored\": %lld, \"finalised\": %lld, \"detections\": %lld, "
                    "\"detection_in_active_map\": %lld, \"detection_reopened_map\": %lld, \"detection_known_object\": %lld, "
                    "\"detection_no_free_map\": %lld, \"objects_left_to_other_map\": %lld, \"objects_duplicate\": %lld, "
                    "\"ps_pings_replayed\": %lld, \"fls_frames_replayed\": %lld, \"fls_frames_judged_later\": %lld, "
                    "\"fls_shadows\": %lld},\n",
                 static_cast<long long>(c.map_initialisations), static_cast<long long>(c.maps_finalised),
                 static_cast<long long>(c.detections), static_cast<long long>(c.detection_in_active_map),
                 static_cast<long long>(c.detection_reopened_map),
                 static_cast<long long>(c.detection_known_object), static_cast<long long>(c.detection_no_free_map),
                 static_cast<long long>(c.objects_left_to_other_map), static_cast<long long>(c.objects_duplicate),
                 static_cast<long long>(c.ps_pings_replayed), static_cast<long long>(c.fls_frames_replayed),
                 static_cast<long long>(c.fls_frames_judged_later), static_cast<long long>(c.fls_shadows));
    std::fprintf(f, "  \"objects\": %lld, \"peak_rss_kb\": %ld\n}\n", static_cast<long long>(c.objects_published),
                 peakRssKb());
    const bool ok = std::fclose(f) == 0;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot write " + path);
}

void printSummary(MapperNode& node, const MapOutputs& outs) {
    const mapper_status_t& s = node.status();
    std::printf("state %s  variant %s  nav %lld  fls %lld/%lld used  ps %lld/%lld used\n", s.state.c_str(),
                s.variant.c_str(), static_cast<long long>(s.nav_in), static_cast<long long>(s.fls_used),
                static_cast<long long>(s.fls_in), static_cast<long long>(s.ps_used), static_cast<long long>(s.ps_in));
    std::printf("map centre %.2f %.2f %.2f  seq gaps nav/fls/ps %lld/%lld/%lld  proc p99 %.0f us max %.0f us\n",
                s.map_centre[0], s.map_centre[1], s.map_centre[2], static_cast<long long>(s.nav_seq_gaps),
                static_cast<long long>(s.fls_seq_gaps), static_cast<long long>(s.ps_seq_gaps), s.proc_p99_us,
                s.proc_max_us);
    for (int i = 0; i < s.num_reasons; ++i)
        if (s.reason_count[i] > 0) std::printf("  %-24s %lld\n", s.reason_name[i].c_str(), static_cast<long long>(s.reason_count[i]));
    const MapperCounters& c = node.mapper().counters();
    std::printf("maps %lld anchored, %lld finalised; detections %lld (%lld in an active map, %lld reopened a "
                "finalised map, %lld on a published object, %lld with no free map); %lld held PS pings and %lld "
                "held FLS frames replayed; %lld FLS frames judged against a seabed found after them; %lld FLS shadows\n",
                static_cast<long long>(c.map_initialisations), static_cast<long long>(c.maps_finalised),
                static_cast<long long>(c.detections), static_cast<long long>(c.detection_in_active_map),
                static_cast<long long>(c.detection_reopened_map), static_cast<long long>(c.detection_known_object),
                static_cast<long long>(c.detection_no_free_map), static_cast<long long>(c.ps_pings_replayed),
                static_cast<long long>(c.fls_frames_replayed), static_cast<long long>(c.fls_frames_judged_later),
                static_cast<long long>(c.fls_shadows));
    for (const std::string& line : outs.summary) std::printf("%s\n", line.c_str());
}

// Offline: the log through the same path as live, read by our own reader,
// which resynchronises after damage (finding 2). Returns 3 when events were
// lost to damage (the map of everything readable is still written).
int runOffline(MapperNode& node, const std::string& log_path) {
    const MapperConfig& m = node.config().mapper;
    // The largest message the config allows (an FLS frame), with room for headers.
    const std::size_t max_data = static_cast<std::size_t>(m.fls.beams) * m.fls.rows +
                                 4 * static_cast<std::size_t>(m.fls.beams + m.fls.rows) + 4096;
    LcmLogReader log(log_path, max_data);
    if (!log.good()) {
        spdlog::error("cannot read LCM log {}", log_path);
        return 2;
    }
    const int64_t resume_at = node.inputPosition();  // events a resumed checkpoint has consumed
    int64_t events = 0;
    LcmLogEvent ev;
    while (log.next(ev)) {
        ++events;
        if (events <= resume_at) continue;
        node.setInputPosition(events);  // a checkpoint taken while handling it has consumed it
        node.handle(std::string(ev.channel), ev.data, ev.size);
        if (g_stop) break;
    }
    node.flush(true);
    spdlog::info("read {} events from {}{}", events, log_path,
                 resume_at > 0 ? fmt::format(" (resumed after {})", resume_at) : std::string());
    const LcmLogStats& st = log.stats();
    if (log.lostData()) {
        spdlog::error("{}: damaged log: {} damaged region(s), {} byte(s) skipped{}", log_path, st.damaged_regions,
                      st.skipped_bytes, st.truncated_tail ? ", cut mid-event at the end" : "");
        return 3;
    }
    return 0;
}

class LiveHandler {
public:
    explicit LiveHandler(MapperNode& n) : node_(n) {}
    void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
        node_.handle(channel, rbuf->data, rbuf->data_size);
    }

private:
    MapperNode& node_;
};

int runLive(MapperNode& node, lcm::LCM& lcm) {
    LiveHandler h(node);
    const DaemonConfig& c = node.config();
    for (const std::string& ch : {c.nav_channel, c.fls_channel, c.ps_channel}) {
        lcm::Subscription* sub = lcm.subscribe(ch, &LiveHandler::onMessage, &h);
        sub->setQueueCapacity(c.queue_capacity);  // the default 30 drops the newest in a burst
    }
    spdlog::info("listening on {} / {} / {}", c.nav_channel, c.fls_channel, c.ps_channel);
    int64_t last_status = wallUs();
    while (!g_stop) {
        if (lcm.handleTimeout(100) < 0) {
            if (g_stop) break;  // the signal interrupted select(): a normal stop
            spdlog::error("LCM handle failed");
            return 2;
        }
        node.tick(wallUs());
        if (wallUs() - last_status > static_cast<int64_t>(c.status_period_s * 1e6)) {
            node.publishStatus();
            last_status = wallUs();
        }
    }
    // Finding 10: what is queued when the stop comes is still handled (and its
    // gaps counted), bounded so a flood cannot keep the daemon from stopping.
    for (int i = 0; i < 4 * c.queue_capacity && lcm.handleTimeout(0) > 0; ++i) {
    }
    node.flush(true);  // finish what is in hand
    return 0;
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"sf-mapper: FLS + profiling-sonar fusion mapper daemon"};
    std::string config_path, log_path, map_out, variant, lcm_url, status_out, checkpoint_path;
    bool quiet = false, resume = false, check_checkpoint = false;
    app.add_option("--config", config_path, "mapper YAML config (docs/mapper-config.md)")->required()->check(CLI::ExistingFile);
    app.add_option("--log", log_path, "offline: read this LCM log as fast as possible instead of listening")->check(CLI::ExistingFile);
    app.add_option("--map-out", map_out, "the first map's file (binary; a .ply is written beside it)");
    std::string map_dir;
    app.add_option("--map-dir", map_dir,
                   "survey: every finalised map as map_<id>.map (+ .map.ply, + .objects.json) in this folder");
    app.add_option("--variant", variant, variantChoices() + " (overrides the config's preset)");
    app.add_option("--lcm-url", lcm_url, "LCM provider URL (live mode)");
    app.add_option("--status-out", status_out, "write the final status (counts, timing) as JSON here");
    app.add_option("--checkpoint", checkpoint_path,
                   "write a crash-safe checkpoint here every daemon.checkpoint_period_s and at exit");
    app.add_flag("--resume", resume, "start from the --checkpoint file if it exists (a damaged or foreign one is an error)");
    app.add_flag("--check-checkpoint", check_checkpoint,
                 "only check that the --checkpoint file loads with this config (exit 0) or say why not (exit 2)");
    app.add_flag("--quiet", quiet, "no summary on stdout");
    std::string octomap_out;
#ifdef SF_WITH_OCTOMAP
    app.add_option("--octomap-out", octomap_out,
                   "also write the final map as an OctoMap OcTree binary (.bt, ENU) for octovis (docs/map-format.md)");
#endif
    CLI11_PARSE(app, argc, argv);

    DaemonConfig cfg;
    try {
        cfg = loadDaemonConfig(config_path);
        if (!variant.empty()) {
            applyVariant(requireVariant(variant, "--variant"), cfg.mapper);
            cfg.variant = variant;
        }
        if (!lcm_url.empty()) cfg.lcm_url = lcm_url;
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    if (check_checkpoint) {
        if (checkpoint_path.empty()) {
            spdlog::error("--check-checkpoint needs --checkpoint PATH");
            return 2;
        }
        try {
            const std::vector<uint8_t> state = readCheckpoint(checkpoint_path, configFingerprint(cfg));
            MapperNode node(cfg, {});
            StateReader r(state.data(), state.size());
            if (!node.loadState(r)) throw std::runtime_error("checkpoint " + checkpoint_path + ": contents do not fit");
            std::printf("checkpoint %s: ok (%lld NAV, map %s)\n", checkpoint_path.c_str(),
                        static_cast<long long>(node.mapper().counters().nav_in),
                        node.mapper().map().initialised() ? "anchored" : "not anchored");
            return 0;
        } catch (const std::exception& e) {
            spdlog::error("{}", e.what());
            return 2;
        }
    }
    if (map_out.empty() && map_dir.empty()) {
        spdlog::error("--map-out or --map-dir is required");
        return 2;
    }
    if (resume && checkpoint_path.empty()) {
        spdlog::error("--resume needs --checkpoint PATH");
        return 2;
    }
    try {
        if (!map_out.empty()) checkWritable(map_out, "map (--map-out)");
        if (!map_dir.empty()) checkWritable(map_dir + "/map_probe", "map folder (--map-dir)");
        if (!octomap_out.empty()) checkWritable(octomap_out, "OctoMap (--octomap-out)");
        if (!status_out.empty()) checkWritable(status_out, "status (--status-out)");
        if (!checkpoint_path.empty()) checkWritable(checkpoint_path, "checkpoint (--checkpoint)");
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
    }
    // Finding 11: a hang-up stops the daemon like SIGINT/SIGTERM (map written).
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    std::signal(SIGHUP, onSignal);
    std::signal(SIGPIPE, SIG_IGN);

    try {
        std::unique_ptr<lcm::LCM> lcm;
        MapperNode::Publisher pub;
        if (log_path.empty()) {
            lcm = std::make_unique<lcm::LCM>(cfg.lcm_url);
            if (!lcm->good()) {
                spdlog::error("cannot open LCM at {}", cfg.lcm_url);
                return 2;
            }
            pub.status = [&](const mapper_status_t& m) { lcm->publish(cfg.status_channel, &m); };
            pub.objects = [&](const objects_t& m) { lcm->publish(cfg.objects_channel, &m); };
            pub.map = [&](const map_snapshot_t& m) { lcm->publish(cfg.map_channel, &m); };
        }
        MapOutputs outs{map_out, map_dir};
#ifdef SF_WITH_OCTOMAP
        // The occupied set of the first map (the map --map-out holds; octomap_export.hpp).
        auto writeOctomapOf = [&](const VoxelMap& map) {
            const OctomapExportStats st = writeOctomap(octomap_out, map, cfg.mapper.segmentation.occupied_probability);
            spdlog::info("OctoMap written to {} ({} occupied, {} free voxels)", octomap_out, st.occupied, st.free);
        };
#endif
        pub.finalised = [&](const FinalisedMap& f) {
            onFinalised(f, cfg, outs);
#ifdef SF_WITH_OCTOMAP
            if (f.map_id == 1 && !octomap_out.empty()) {
                try {
                    writeOctomapOf(f.map);
                } catch (const std::exception& e) {
                    spdlog::error("map 1: {}", e.what());
                    ++outs.write_failures;
                }
            }
#endif
        };
        MapperNode* node_ptr = nullptr;
        std::unique_ptr<CheckpointWriter> checkpoints;
        double checkpoint_copy_max_us = 0.0;  // the message thread's share of a checkpoint
        if (!checkpoint_path.empty())
            pub.checkpoint = [&] {
                if (!checkpoints) return;
                const auto t0 = std::chrono::steady_clock::now();
                (void)checkpoints->submit([&](StateWriter& w) { node_ptr->saveState(w); });
                checkpoint_copy_max_us = std::max(
                    checkpoint_copy_max_us,
                    std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
            };
        MapperNode node(cfg, pub);
        node_ptr = &node;
        if (!checkpoint_path.empty()) {
            const uint64_t fingerprint = configFingerprint(cfg);
            if (resume && access(checkpoint_path.c_str(), F_OK) == 0) {
                const std::vector<uint8_t> state = readCheckpoint(checkpoint_path, fingerprint);
                StateReader r(state.data(), state.size());
                if (!node.loadState(r)) {
                    spdlog::error("checkpoint {}: its contents do not fit this config (damaged or foreign)",
                                  checkpoint_path);
                    return 2;
                }
                spdlog::info("resumed from checkpoint {} (map {}, {} NAV so far)", checkpoint_path,
                             node.mapper().map().initialised() ? "anchored" : "not anchored",
                             node.mapper().counters().nav_in);
            } else if (resume) {
                spdlog::warn("no checkpoint at {} yet: starting fresh", checkpoint_path);
            }
            checkpoints = std::make_unique<CheckpointWriter>(checkpoint_path, node.stateBytesBound(), fingerprint);
        }
        int rc = log_path.empty() ? runLive(node, *lcm) : runOffline(node, log_path);
        if (rc != 0 && rc != 3) return rc;
        if (checkpoints) {  // the final state, synchronously
            checkpoints->drain();
            if (!checkpoints->submit([&](StateWriter& w) { node.saveState(w); })) spdlog::error("final checkpoint failed");
            checkpoints->drain();
            spdlog::info("checkpoints: {} written, {} failed, {} skipped (writer busy); copy on the message thread "
                         "at most {:.0f} us",
                         checkpoints->written(), checkpoints->failed(), checkpoints->skipped(), checkpoint_copy_max_us);
        }
        writeOutputs(node, outs);
#ifdef SF_WITH_OCTOMAP
        // No map was ever anchored: the empty map, as --map-out.
        if (!octomap_out.empty() && node.mapper().counters().map_initialisations == 0) writeOctomapOf(node.mapper().map());
#endif
        if (lcm) node.publishStatus();
        if (!status_out.empty()) writeStatusJson(node, status_out);
        if (!quiet) printSummary(node, outs);
        if (rc == 3) return 3;
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 1;
    }
    return 0;
}
