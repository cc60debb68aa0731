// hostile_stream: replays a valid LCM log with bad messages mixed in and/or
// FLS and PS messages dropped, either live on LCM (paced by the log's time
// stamps) or into a new log file. Writes a JSON summary of what it injected
// (per kind, with the daemon reason each must be counted under) and dropped.
// Used by tests/robust (issue 10: mixed bad stream, drops, load).
//
//   hostile_stream --log IN [--out-log OUT | --lcm-url URL --rate R] [--bad N] [--drop-fls P] [--drop-ps P]
//                  [--seed S] [--burst K] --summary JSON
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

#include "lcm_log_reader.hpp"

using namespace sonarfusion;
using Bytes = std::vector<uint8_t>;

namespace {
template <class Msg>
Bytes encode(const Msg& m) {
    Bytes b(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
}
void putInt32(Bytes& b, std::size_t off, int32_t v) {
    const uint32_t u = static_cast<uint32_t>(v);
    b[off] = u >> 24, b[off + 1] = (u >> 16) & 0xff, b[off + 2] = (u >> 8) & 0xff, b[off + 3] = u & 0xff;
}
// Byte offset of ps_ping_t.num_bins in an encoding of `p`.
std::size_t psBinsOffset(const ps_ping_t& p) { return 8 + 8 + 8 + 4 + p.sensor_name.size() + 1 + 12 + 8 + 24; }

struct Kind {
    const char* name;
    const char* reason;  // the MAPPER_STATUS reason it must be counted under
    const char* channel;
};
// Each kind is made from the latest valid message of its channel.
const Kind kKinds[] = {
    {"bad_fingerprint", "bad_fingerprint", "FLS"}, {"truncated", "truncated", "PS"},
    {"trailing_bytes", "trailing_bytes", "NAV"},   {"negative_count", "bad_count", "PS"},
    {"huge_count", "bad_count", "PS"},             {"nav_nan_pose", "nav_non_finite", "NAV"},
    {"nav_inf_attitude", "nav_non_finite", "NAV"}, {"image_size_vs_geometry", "fls_size_mismatch", "FLS"},
    {"empty_ping", "ps_empty", "PS"},              {"duplicate", "duplicate", "PS"},
    {"backward_utime", "stale", "FLS"},            {"nav_stamp_int64_max", "nav_time_jump", "NAV"},
    {"nav_stamp_10s_back", "nav_time_jump", "NAV"}, {"ps_head_angle_3rad", "ps_geometry_mismatch", "PS"},
    {"fls_tilt_nan", "fls_geometry_mismatch", "FLS"},
};
constexpr int kKindCount = sizeof(kKinds) / sizeof(kKinds[0]);

struct Latest {
    nav_state_t nav;
    fls_image_t fls;
    ps_ping_t ps;
    bool have_nav = false, have_fls = false, have_ps = false;
};

Bytes makeBad(int kind, const Latest& l) {
    const std::string k = kKinds[kind].name;
    if (k == "bad_fingerprint") {
        Bytes b = encode(l.fls);
        b[0] ^= 0x5a;
        return b;
    }
    if (k == "truncated") {
        Bytes b = encode(l.ps);
        b.resize(b.size() - 7);
        return b;
    }
    if (k == "trailing_bytes") {
        Bytes b = encode(l.nav);
        b.insert(b.end(), {1, 2, 3});
        return b;
    }
    if (k == "negative_count" || k == "huge_count") {
        Bytes b = encode(l.ps);
        putInt32(b, psBinsOffset(l.ps), k == "negative_count" ? -5 : 0x7fffffff);
        return b;
    }
    if (k == "nav_nan_pose" || k == "nav_inf_attitude") {
        nav_state_t n = l.nav;
        n.utime += 1;  // between two valid samples
        if (k == "nav_nan_pose") n.position_ned[1] = std::numeric_limits<double>::quiet_NaN();
        else n.rpy[2] = std::numeric_limits<double>::infinity();
        return encode(n);
    }
    if (k == "image_size_vs_geometry") {
        fls_image_t f = l.fls;
        f.utime += 1;
        f.data_size -= 1;
        f.data.resize(static_cast<std::size_t>(f.data_size));
        return encode(f);
    }
    if (k == "empty_ping") {
        ps_ping_t p = l.ps;
        p.utime += 1;
        p.num_bins = 0;
        p.intensity.clear();
        return encode(p);
    }
    if (k == "duplicate") return encode(l.ps);
    if (k == "backward_utime") {
        fls_image_t f = l.fls;
        f.utime -= 10000000;
        return encode(f);
    }
    if (k == "nav_stamp_int64_max" || k == "nav_stamp_10s_back") {
        nav_state_t n = l.nav;
        n.utime = k == "nav_stamp_int64_max" ? std::numeric_limits<int64_t>::max() : n.utime - 10000000;
        return encode(n);
    }
    if (k == "ps_head_angle_3rad") {
        ps_ping_t p = l.ps;
        p.utime += 1;
        p.head_angle = 3.0f;
        return encode(p);
    }
    fls_image_t f = l.fls;  // fls_tilt_nan
    f.utime += 1;
    f.tilt = std::numeric_limits<float>::quiet_NaN();
    return encode(f);
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"hostile_stream: a valid LCM log replayed with bad messages mixed in and messages dropped"};
    std::string in, out_log, url, summary;
    double rate = 10.0, drop_fls = 0.0, drop_ps = 0.0;
    int bad = 0, burst = 0;
    unsigned seed = 1;
    app.add_option("--log", in, "valid LCM log")->required();
    app.add_option("--out-log", out_log, "write the stream to this log instead of publishing");
    app.add_option("--lcm-url", url, "publish live on this LCM URL");
    app.add_option("--rate", rate, "live pace: N times the log's real time (0: as fast as possible)");
    app.add_option("--bad", bad, "bad messages to mix in (kinds in turn)");
    app.add_option("--drop-fls", drop_fls, "fraction of FLS messages to drop");
    app.add_option("--drop-ps", drop_ps, "fraction of PS messages to drop");
    app.add_option("--burst", burst, "live: publish every K-th stretch of 1000 events with no pacing (0: never)");
    app.add_option("--seed", seed, "random seed");
    app.add_option("--summary", summary, "JSON summary")->required();
    CLI11_PARSE(app, argc, argv);
    if (out_log.empty() == url.empty()) {
        std::fprintf(stderr, "give exactly one of --out-log and --lcm-url\n");
        return 2;
    }

    LcmLogReader reader(in, 64u << 20);
    if (!reader.good()) {
        std::fprintf(stderr, "cannot read %s\n", in.c_str());
        return 2;
    }
    // Count the events first to spread the bad messages over the middle of the run.
    // A message lost at either end of a channel's stream leaves no gap in the
    // sequence numbers, so the first and last of each channel are never dropped.
    int64_t total = 0;
    std::map<std::string, int64_t> per_channel, seen;
    {
        LcmLogEvent ev;
        while (reader.next(ev)) ++total, ++per_channel[std::string(ev.channel)];
    }
    LcmLogReader log(in, 64u << 20);
    std::unique_ptr<lcm::LogFile> writer;
    std::unique_ptr<lcm::LCM> lcm;
    if (!out_log.empty()) {
        writer = std::make_unique<lcm::LogFile>(out_log, "w");
        if (!writer->good()) return 2;
    } else {
        lcm = std::make_unique<lcm::LCM>(url);
        if (!lcm->good()) return 2;
    }
    int64_t written = 0;
    auto emit = [&](const std::string& channel, const uint8_t* data, std::size_t size, int64_t utime) {
        if (writer) {
            lcm::LogEvent e;
            e.eventnum = written;
            e.timestamp = utime;
            e.channel = channel;
            e.datalen = static_cast<int32_t>(size);
            e.data = const_cast<uint8_t*>(data);
            writer->writeEvent(&e);
        } else {
            lcm->publish(channel, data, static_cast<unsigned>(size));
        }
        ++written;
    };

    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    Latest latest;
    std::map<std::string, int64_t> injected, dropped{{"FLS", 0}, {"PS", 0}}, passed{{"NAV", 0}, {"FLS", 0}, {"PS", 0}};
    // Bad messages go after event `start` every `every` events.
    const int64_t start = total / 10, every = bad > 0 ? std::max<int64_t>(1, (total * 7 / 10) / bad) : 0;
    int next_kind = 0, made = 0, wanted = -1;
    int64_t index = 0, first_utime = -1;
    const auto t0 = std::chrono::steady_clock::now();
    LcmLogEvent ev;
    while (log.next(ev)) {
        const std::string channel(ev.channel);
        if (lcm && rate > 0.0 && !(burst > 0 && (index / 1000) % burst == burst - 1)) {
            if (first_utime < 0) first_utime = ev.utime;
            const auto due = t0 + std::chrono::microseconds(static_cast<int64_t>((ev.utime - first_utime) / rate));
            std::this_thread::sleep_until(due);
        }
        // Unpaced: pause before the last 30 events so the receiver drains its
        // queue; their arrival then shows, as sequence gaps, everything lost before.
        if (lcm && rate <= 0.0 && index == total - 30) std::this_thread::sleep_for(std::chrono::seconds(1));
        ++index;
        const int64_t nth = ++seen[channel];
        const bool end = nth == 1 || nth == per_channel[channel];
        const bool drop =
            !end && ((channel == "FLS" && u01(rng) < drop_fls) || (channel == "PS" && u01(rng) < drop_ps));
        if (drop) {
            ++dropped[channel];
            continue;
        }
        emit(channel, ev.data, ev.size, ev.utime);
        ++passed[channel];
        if (channel == "NAV") latest.have_nav = latest.nav.decode(ev.data, 0, static_cast<int>(ev.size)) > 0;
        if (channel == "FLS") latest.have_fls = latest.fls.decode(ev.data, 0, static_cast<int>(ev.size)) > 0;
        if (channel == "PS") latest.have_ps = latest.ps.decode(ev.data, 0, static_cast<int>(ev.size)) > 0;
        // Kinds in strict turn; each goes right after the next valid message of
        // its channel (so a copy is still waiting or was just processed).
        if (every > 0 && made < bad && wanted < 0 && index > start && (index - start) % every == 0) {
            wanted = next_kind;
            next_kind = (next_kind + 1) % kKindCount;
        }
        if (wanted >= 0 && channel == kKinds[wanted].channel &&
            ((channel == "NAV" && latest.have_nav) || (channel == "FLS" && latest.have_fls) ||
             (channel == "PS" && latest.have_ps))) {
            const Bytes b = makeBad(wanted, latest);
            emit(channel, b.data(), b.size(), ev.utime);
            ++injected[kKinds[wanted].name];
            ++made;
            wanted = -1;
        }
    }
    if (made < bad) {
        std::fprintf(stderr, "only %d of %d bad messages placed\n", made, bad);
        return 1;
    }
    std::ofstream js(summary);
    js << "{\n  \"events_in\": " << total << ", \"events_out\": " << written << ",\n  \"passed\": {";
    const char* sep = "";
    for (const auto& [k, v] : passed) js << sep << "\"" << k << "\": " << v, sep = ", ";
    js << "},\n  \"dropped\": {\"FLS\": " << dropped["FLS"] << ", \"PS\": " << dropped["PS"] << "},\n  \"injected\": [";
    sep = "";
    for (const Kind& k : kKinds)
        if (injected[k.name] > 0)
            js << sep << "\n    {\"kind\": \"" << k.name << "\", \"reason\": \"" << k.reason << "\", \"count\": "
               << injected[k.name] << "}",
                sep = ",";
    js << "\n  ]\n}\n";
    std::printf("%lld events out (%d bad, %lld FLS and %lld PS dropped)\n", static_cast<long long>(written), made,
                static_cast<long long>(dropped["FLS"]), static_cast<long long>(dropped["PS"]));
    return 0;
}
