// Seed corpora for the fuzzers, so each starts past the first checks:
//   make_fuzz_corpus DIR [mapper_input|lcm_log|map_file|checkpoint]   (default mapper_input)
// mapper_input: NAV, FLS and PS encodings with the channel byte in front, most
// of them valid for the daemon's default configuration (geometry included);
// lcm_log: the three limit bytes of fuzz_lcm_log, then small logs of those
// messages (one whole, one with a damaged event, one cut short);
// map_file: small maps as saveMap writes them.
#include "checkpoint.hpp"
#include "checkpoint_fuzz_config.hpp"
#include "mapper_node.hpp"
#include <fstream>
#include <iterator>
#include <cstdio>
#include <cstdio>
#include <string>
#include <vector>

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

#include "map_file.hpp"
#include "mapper_node.hpp"

namespace {
void writeFile(const std::string& dir, const char* name, const std::vector<uint8_t>& bytes) {
    FILE* f = std::fopen((dir + "/" + name).c_str(), "wb");
    if (!f) return;
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
}

template <class Msg>
std::vector<uint8_t> encode(const Msg& m) {
    std::vector<uint8_t> buf(m.getEncodedSize());
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return buf;
}

struct Messages {
    std::vector<uint8_t> nav, fls, ps;
};

// Small messages (for the log and as odd seeds): their geometry is not the
// configured sonar's, so the daemon refuses them early.
Messages smallMessages() {
    sonarfusion::nav_state_t nav{};
    nav.utime = 1000;
    nav.position_ned[2] = 16.9;
    sonarfusion::fls_image_t fls{};
    fls.utime = 1000;
    fls.num_beams = 4;
    fls.beam_bearing.assign(4, 0.1f);
    fls.num_ranges = 8;
    fls.row_range.assign(8, 2.0f);
    fls.data_size = 32;
    fls.data.assign(32, static_cast<int8_t>(-56));
    sonarfusion::ps_ping_t ps{};
    ps.utime = 1000;
    ps.range_max = 10.0f;
    ps.num_bins = 50;
    ps.intensity.assign(50, 20);
    return {encode(nav), encode(fls), encode(ps)};
}

// Messages that pass every check of the daemon's default configuration (the
// one fuzz_mapper_input uses), so the fuzzer starts inside libfusion.
struct Configured {
    std::vector<std::vector<uint8_t>> nav;
    std::vector<uint8_t> fls, ps;
};

Configured configuredMessages() {
    const sonarfusion::DaemonConfig cfg{};
    const sonarfusion::MapperNode node(cfg, {});
    const sonarfusion::FlsModel& model = node.mapper().flsModel();
    const sonarfusion::MapperConfig& c = cfg.mapper;
    Configured out;
    for (int i = 0; i < 3; ++i) {
        sonarfusion::nav_state_t nav{};
        nav.utime = 1'000'000 + 100'000 * i;
        nav.seq = i;
        nav.position_ned[0] = 0.05 * i;
        nav.position_ned[2] = 16.9;
        nav.velocity_ned[0] = 0.5;
        nav.altitude = 3.0;
        out.nav.push_back(encode(nav));
    }
    sonarfusion::fls_image_t fls{};
    fls.utime = 1'150'000;
    fls.mount_xyz[0] = static_cast<float>(c.fls_mount.x);
    fls.mount_xyz[1] = static_cast<float>(c.fls_mount.y);
    fls.mount_xyz[2] = static_cast<float>(c.fls_mount.z);
    fls.mount_roll_yaw[0] = static_cast<float>(c.fls_mount.roll);
    fls.mount_roll_yaw[1] = static_cast<float>(c.fls_mount.yaw);
    fls.tilt = static_cast<float>(c.fls.tilt);
    fls.elevation_min = static_cast<float>(c.fls.elevation_min);
    fls.elevation_max = static_cast<float>(c.fls.elevation_max);
    fls.num_beams = model.cols();
    for (int b = 0; b < model.cols(); ++b) fls.beam_bearing.push_back(static_cast<float>(model.bearingOfColumn(b)));
    fls.num_ranges = model.rows();
    for (int r = 0; r < model.rows(); ++r) fls.row_range.push_back(static_cast<float>(model.rangeOfRow(r)));
    fls.data_size = fls.num_beams * fls.num_ranges;
    fls.data.assign(static_cast<std::size_t>(fls.data_size), 0);
    for (int b = 0; b < fls.num_beams; ++b)  // a bright arc a third of the way out
        fls.data[static_cast<std::size_t>(fls.num_ranges / 3 * fls.num_beams + b)] = static_cast<int8_t>(-56);
    out.fls = encode(fls);
    sonarfusion::ps_ping_t ps{};
    ps.utime = 1'120'000;
    ps.mount_xyz[0] = static_cast<float>(c.ps_mount.x);
    ps.mount_xyz[1] = static_cast<float>(c.ps_mount.y);
    ps.mount_xyz[2] = static_cast<float>(c.ps_mount.z);
    ps.mount_roll_yaw[0] = static_cast<float>(c.ps_mount.roll);
    ps.mount_roll_yaw[1] = static_cast<float>(c.ps_mount.yaw);
    ps.tilt = static_cast<float>(c.ps.tilt);
    ps.head_angle = 0.0f;
    ps.fan_min = static_cast<float>(c.ps.fan_min);
    ps.fan_max = static_cast<float>(c.ps.fan_max);
    ps.range_min = static_cast<float>(c.ps.range_min);
    ps.range_max = static_cast<float>(c.ps.range_max);
    ps.num_bins = c.ps.bins;
    ps.intensity.assign(static_cast<std::size_t>(c.ps.bins), 5);
    ps.intensity[static_cast<std::size_t>(c.ps.bins / 2)] = 120;
    out.ps = encode(ps);
    return out;
}

void putBe(std::vector<uint8_t>& b, uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void logEvent(std::vector<uint8_t>& b, int64_t num, const std::string& channel, const std::vector<uint8_t>& data) {
    putBe(b, 0xEDA1DA01u, 4);
    putBe(b, static_cast<uint64_t>(num), 8);
    putBe(b, static_cast<uint64_t>(1'700'000'000'000'000 + num * 100'000), 8);
    putBe(b, channel.size(), 4);
    putBe(b, data.size(), 4);
    b.insert(b.end(), channel.begin(), channel.end());
    b.insert(b.end(), data.begin(), data.end());
}

void mapperInput(const std::string& dir) {
    auto withChannel = [](uint8_t c, std::vector<uint8_t> v) {
        v.insert(v.begin(), c);
        return v;
    };
    const Messages m = smallMessages();
    writeFile(dir, "small_nav", withChannel(0, m.nav));
    writeFile(dir, "small_fls", withChannel(1, m.fls));
    writeFile(dir, "small_ps", withChannel(2, m.ps));
    const Configured c = configuredMessages();
    for (std::size_t i = 0; i < c.nav.size(); ++i)
        writeFile(dir, ("nav" + std::to_string(i)).c_str(), withChannel(0, c.nav[i]));
    writeFile(dir, "fls", withChannel(1, c.fls));
    writeFile(dir, "fls_flush", withChannel(0x81, c.fls));  // bit 7: flush after it
    writeFile(dir, "ps", withChannel(2, c.ps));
}

void lcmLog(const std::string& dir) {
    const Messages m = smallMessages();
    // Limits: max data 255 * 33 bytes, channels up to 255, read-ahead 5 bytes.
    std::vector<uint8_t> whole = {0xFF, 0x00, 0x01};
    int64_t num = 0;
    for (int round = 0; round < 3; ++round) {
        logEvent(whole, num++, "NAV", m.nav);
        logEvent(whole, num++, "FLS", m.fls);
        logEvent(whole, num++, "PS", m.ps);
    }
    writeFile(dir, "log_whole", whole);
    std::vector<uint8_t> damaged = whole;
    damaged[3 + 4 + 8 + 8 + 4 + 3] ^= 0x40;  // the first event's data length
    writeFile(dir, "log_damaged", damaged);
    std::vector<uint8_t> cut(whole.begin(), whole.end() - 17);
    cut[0] = 0x08;  // max data 264 bytes: the FLS and PS events are too long for it
    cut[2] = 0x00;  // no read-ahead
    writeFile(dir, "log_cut_small_limits", cut);
}

void mapFile(const std::string& dir) {
    sonarfusion::MapConfig c;
    c.nx = 3, c.ny = 2, c.nz = 2;
    c.resolution = 0.5;
    sonarfusion::VoxelMap map(c);
    const std::string a = dir + "/map_empty";
    sonarfusion::saveMap(a, map, "fused");
    map.initialiseAt(Eigen::Vector3d(2.0, -1.0, 16.0));
    for (std::size_t i = 0; i < map.size(); ++i) {
        map.setLogOdds(i, 0.4f * static_cast<float>(i) - 2.0f);
        map.setFlags(i, static_cast<uint8_t>(i * 13));
    }
    sonarfusion::saveMap(dir + "/map_anchored", map, "carve_only");
}
// Valid states of the fuzzer's small config: after NAV and pings (some still
// waiting), as a whole file (first byte odd) and as a bare payload (even).
void checkpoints(const std::string& dir) {
    const sonarfusion::DaemonConfig cfg = sffuzz::checkpointFuzzConfig();
    sonarfusion::MapperNode node(cfg, {});
    for (int i = 0; i < 40; ++i) {
        sonarfusion::nav_state_t n{};
        n.utime = 1000000 + i * 20000;
        n.seq = i;
        n.position_ned[0] = 0.01 * i;
        n.position_ned[2] = 16.9;
        std::vector<uint8_t> b(static_cast<std::size_t>(n.getEncodedSize()));
        n.encode(b.data(), 0, static_cast<int>(b.size()));
        node.handle(cfg.nav_channel, b.data(), b.size());
        sonarfusion::ps_ping_t p{};
        p.utime = n.utime + 30000;  // waits for the next NAV
        p.seq = i;
        p.tilt = static_cast<float>(cfg.mapper.ps.tilt);
        p.fan_min = static_cast<float>(cfg.mapper.ps.fan_min);
        p.fan_max = static_cast<float>(cfg.mapper.ps.fan_max);
        p.range_max = static_cast<float>(cfg.mapper.ps.range_max);
        p.num_bins = cfg.mapper.ps.bins;
        p.intensity.assign(static_cast<std::size_t>(p.num_bins), 0);
        p.intensity[240] = 100;
        std::vector<uint8_t> q(static_cast<std::size_t>(p.getEncodedSize()));
        p.encode(q.data(), 0, static_cast<int>(q.size()));
        node.handle(cfg.ps_channel, q.data(), q.size());
    }
    std::vector<uint8_t> payload(node.stateBytesBound());
    sonarfusion::StateWriter w(payload.data(), payload.size());
    node.saveState(w);
    payload.resize(w.size());
    std::vector<uint8_t> bare{0};
    bare.insert(bare.end(), payload.begin(), payload.end());
    writeFile(dir, "payload", bare);
    const std::string path = dir + "/.checkpoint.tmpfile";
    {
        sonarfusion::CheckpointWriter cw(path, node.stateBytesBound(), sonarfusion::configFingerprint(cfg));
        (void)cw.submit([&](sonarfusion::StateWriter& sw) { node.saveState(sw); });
        cw.drain();
    }
    std::ifstream f(path, std::ios::binary);
    std::vector<uint8_t> file{1};
    file.insert(file.end(), std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    std::remove(path.c_str());
    writeFile(dir, "file", file);
}
}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) return 2;
    const std::string kind = argc == 3 ? argv[2] : "mapper_input";
    if (kind == "mapper_input") {
        mapperInput(argv[1]);
    } else if (kind == "lcm_log") {
        lcmLog(argv[1]);
    } else if (kind == "map_file") {
        mapFile(argv[1]);
    } else if (kind == "checkpoint") {
        checkpoints(argv[1]);
    } else {
        std::fprintf(stderr, "unknown corpus kind %s\n", kind.c_str());
        return 2;
    }
    return 0;
}
