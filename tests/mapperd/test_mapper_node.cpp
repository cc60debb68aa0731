// The daemon core under hostile streams and configs (issue 10's probe findings
// 3-9): each test fails on ea62504.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

#include "mapper_config_yaml.hpp"
#include "mapper_node.hpp"
#include "node_test_util.hpp"

using namespace sonarfusion;
using sonarfusion::test::encode;
using sonarfusion::test::send;

namespace {
nav_state_t nav(int64_t utime, double x, int64_t seq) {
    nav_state_t n{};
    n.utime = utime;
    n.seq = seq;
    n.position_ned[0] = x;
    n.position_ned[2] = 20.0 - 3.12;
    return n;
}

// A ping as the configured PS would send it, with one echo 4 m out.
ps_ping_t ping(const MapperConfig& c, int64_t utime, int64_t seq) {
    ps_ping_t p = sonarfusion::test::psPing(c, utime, seq);
    p.intensity[200] = static_cast<int8_t>(-56);  // 200 as a byte
    return p;
}

fls_image_t frame(const MapperConfig& c, const FlsModel& model, int64_t utime, int64_t seq) {
    fls_image_t m{};
    m.utime = utime;
    m.seq = seq;
    m.tilt = static_cast<float>(c.fls.tilt);
    m.elevation_min = static_cast<float>(c.fls.elevation_min);
    m.elevation_max = static_cast<float>(c.fls.elevation_max);
    m.num_beams = model.cols();
    for (int b = 0; b < model.cols(); ++b) m.beam_bearing.push_back(static_cast<float>(model.bearingOfColumn(b)));
    m.num_ranges = model.rows();
    for (int r = 0; r < model.rows(); ++r) m.row_range.push_back(static_cast<float>(model.rangeOfRow(r)));
    m.data_size = model.rows() * model.cols();
    m.data.assign(static_cast<std::size_t>(m.data_size), 0);
    return m;
}

int64_t outcome(const MapperNode& n, Outcome o) { return n.mapper().counters().by_outcome[static_cast<int>(o)]; }

std::string writeTemp(const std::string& text) {
    char path[] = "/tmp/sf_cfg_XXXXXX";
    const int fd = mkstemp(path);
    EXPECT_GE(fd, 0);
    close(fd);
    std::ofstream(path) << text;
    return path;
}
}  // namespace

// Finding 3: one NAV stamped INT64_MAX stopped mapping for the rest of the run,
// and one rejected FLS stamped INT64_MAX stamped every later status.
TEST(MapperNodeRobust, OneGlitchStampNeitherStopsMappingNorStampsTheOutputs) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    const MapperConfig& c = node.mapper().config();
    int64_t seq = 0, ps_seq = 0;
    for (int i = 0; i < 200; ++i) {
        const int64_t t = 1000000 + i * 20000;
        if (i == 100) send(node, "NAV", nav(std::numeric_limits<int64_t>::max(), 9.0, seq++));
        if (i == 120) {
            fls_image_t f = frame(c, node.mapper().flsModel(), std::numeric_limits<int64_t>::max(), 0);
            send(node, "FLS", f);
        }
        send(node, "NAV", nav(t, 0.02 * i, seq++));
        send(node, "PS", ping(c, t + 10000, ps_seq++));
    }
    node.flush(true);
    EXPECT_EQ(outcome(node, Outcome::NavTimeJump), 1);
    EXPECT_EQ(outcome(node, Outcome::NavOutOfOrder), 0);
    EXPECT_EQ(node.mapper().counters().ps_used, 199);  // the last ping has no later NAV
    EXPECT_EQ(outcome(node, Outcome::NoPose), 2);        // the last ping and the INT64_MAX frame
    EXPECT_LT(node.status().utime, 1000000 + 200 * 20000);
}

// Finding 4: after a clock step back, sonar was interpolated against stale NAV.
TEST(MapperNodeRobust, SonarAfterAClockStepIsPlacedOnTheNewTimelineOnly) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    const MapperConfig& c = node.mapper().config();
    int64_t seq = 0;
    for (int i = 0; i < 100; ++i) send(node, "NAV", nav(100000000 + i * 20000, 0.02 * i, seq++));
    // The clock steps back 60 s; the vehicle is 50 m further on.
    for (int i = 0; i < 100; ++i) {
        const int64_t t = 40000000 + i * 20000;
        send(node, "PS", ping(c, t - 5000, seq));
        send(node, "NAV", nav(t, 50.0 + 0.02 * i, seq++));
    }
    node.flush(true);
    EXPECT_EQ(node.mapper().counters().nav_timeline_resets, 1);
    // The pings held while the new timeline was being confirmed are placed on it;
    // the one sent before its first NAV cannot be (and is not put on the old one).
    EXPECT_EQ(node.mapper().counters().ps_used, 99);
    EXPECT_EQ(outcome(node, Outcome::NoPose), 1);
    const auto p = node.mapper().navPoseAt(40000000 + 50 * 20000);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->position.x(), 51.0, 1e-6);
}

// Finding 5: message geometry was trusted.
TEST(MapperNodeRobust, PingsAndFramesOutsideTheConfiguredSonarAreCounted) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    const MapperConfig& c = node.mapper().config();
    int64_t seq = 0;
    for (int i = 0; i < 10; ++i) send(node, "NAV", nav(1000000 + i * 20000, 0.0, seq++));
    ps_ping_t far = ping(c, 1010000, 0);
    far.range_max = 100.0f;  // a 10 m sonar
    send(node, "PS", far);
    ps_ping_t head = ping(c, 1030000, 1);
    head.head_angle = 3.0f;
    send(node, "PS", head);
    ps_ping_t tilt = ping(c, 1050000, 2);
    tilt.tilt = std::numeric_limits<float>::quiet_NaN();
    send(node, "PS", tilt);
    send(node, "PS", ping(c, 1070000, 3));  // a good one
    int64_t t = 1090000, fseq = 4;
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), 0.0f}) {
        fls_image_t f = frame(c, node.mapper().flsModel(), t++, fseq++);
        f.tilt = bad;
        send(node, "FLS", f);
        f = frame(c, node.mapper().flsModel(), t++, fseq++);
        f.mount_xyz[2] = std::isnan(bad) ? bad : 0.5f;
        send(node, "FLS", f);
    }
    // The ping's own ranges, bearings and aperture (per-ping geometry, issue 14)
    // are libfusion's to check: NaN, or a window longer than the configured
    // sonar's, is fls_bad_geometry; a narrower aperture is a setting.
    fls_image_t f = frame(c, node.mapper().flsModel(), t++, fseq++);
    f.elevation_max = std::numeric_limits<float>::quiet_NaN();
    send(node, "FLS", f);
    f = frame(c, node.mapper().flsModel(), t++, fseq++);
    f.row_range[0] = 12.0f;
    send(node, "FLS", f);
    f = frame(c, node.mapper().flsModel(), t++, fseq++);
    f.elevation_max = 0.0f;
    send(node, "FLS", f);
    node.flush(true);
    EXPECT_EQ(node.transportRejects(TransportReject::PsGeometryMismatch), 3);
    EXPECT_EQ(node.transportRejects(TransportReject::FlsGeometryMismatch), 4);
    EXPECT_EQ(outcome(node, Outcome::FlsBadGeometry), 2);
    EXPECT_EQ(outcome(node, Outcome::FlsBeforeMap), 1);
    EXPECT_EQ(node.mapper().counters().ps_in, 1);
    EXPECT_FALSE(node.mapper().map().initialised());
}

// A copy of a message already processed or still waiting, or an older one,
// would change the map; each is refused under its own reason.
TEST(MapperNodeRobust, DuplicateAndOlderSonarIsRefused) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    const MapperConfig& c = node.mapper().config();
    for (int i = 0; i < 10; ++i) send(node, "NAV", nav(1000000 + i * 20000, 0.0, i));
    const ps_ping_t waiting = ping(c, 1300000, 1);  // after the newest NAV: waits
    send(node, "PS", waiting);
    send(node, "PS", waiting);
    const ps_ping_t done = ping(c, 1050000, 0);  // bracketed: processed at once
    send(node, "PS", done);
    send(node, "PS", done);
    send(node, "PS", ping(c, 1010000, 2));  // older than one already processed
    EXPECT_EQ(node.transportRejects(TransportReject::Duplicate), 2);
    EXPECT_EQ(node.transportRejects(TransportReject::Stale), 1);
    EXPECT_EQ(node.seqGaps(2), 0);  // refused copies neither count gaps nor move the reference
}

// Finding 6: NAV 4 s late used 0 of 800 FLS frames (16 slots, then a forced flush
// with no NAV). Now the waiting set is thinned and the map degrades gradually.
TEST(MapperNodeRobust, LateNavDegradesGracefully) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    const MapperConfig& c = node.mapper().config();
    const int64_t late = 4000000;  // NAV arrives 4 s after the sonar it brackets
    int64_t nav_seq = 0, ps_seq = 0;
    // 20 s of data: PS at 50 Hz, NAV at 50 Hz, NAV delivered 4 s late.
    for (int64_t t = 0; t <= 20000000; t += 20000) {
        send(node, "PS", ping(c, 1000000 + t + 10000, ps_seq++));
        if (t >= late) send(node, "NAV", nav(1000000 + t - late, 0.001 * (t - late) / 1000.0, nav_seq++));
    }
    node.flush(true);
    const MapperCounters& k = node.mapper().counters();
    // 64 slots over 4 s: about one ping in three is kept and placed.
    EXPECT_GT(k.ps_used, 200);
    EXPECT_GT(node.transportRejects(TransportReject::PendingOverflow), 500);
    EXPECT_EQ(k.ps_used + node.transportRejects(TransportReject::PendingOverflow) + outcome(node, Outcome::NoPose),
              ps_seq);
}

// Finding 9: frames larger than the configured sonar passed the guard and grew
// the buffers (peak RSS 307 MB).
TEST(MapperNodeRobust, FramesLargerThanTheConfiguredSonarAreRefusedBeforeDecode) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    fls_image_t f = frame(node.mapper().config(), node.mapper().flsModel(), 1000, 0);
    f.num_beams = 1024;
    f.beam_bearing.assign(1024, 0.0f);
    f.num_ranges = 1024;
    f.row_range.assign(1024, 1.0f);
    f.data_size = 1024 * 1024;
    f.data.assign(1024 * 1024, 0);
    send(node, "FLS", f);
    ps_ping_t p = ping(node.mapper().config(), 1000, 0);
    p.num_bins = 5000;
    p.intensity.assign(5000, 0);
    send(node, "PS", p);
    EXPECT_EQ(node.transportRejects(TransportReject::BadCount), 2);
    EXPECT_EQ(node.pendingCount(), 0);
}

// Finding 8 (and 9's map size): every bad value is an error naming the key.
TEST(DaemonConfigValidation, BadPeriodsCapacitiesChannelsAndSizesNameTheirKey) {
    const std::pair<std::string, std::string> cases[] = {
        {"daemon: {segment_period_s: 1.0e14}", "daemon.segment_period_s"},
        {"daemon: {map_period_s: 1.0e14}", "daemon.map_period_s"},
        {"daemon: {status_period_s: .nan}", "daemon.status_period_s"},
        {"daemon: {queue_capacity: 0}", "daemon.queue_capacity"},
        {"daemon: {queue_capacity: -1}", "daemon.queue_capacity"},
        {"daemon: {queue_capacity: 2147483647}", "daemon.queue_capacity"},
        {"daemon: {fls_pending_slots: 0}", "daemon.fls_pending_slots"},
        {"channels: {nav: ''}", "channels.nav"},
        {"channels: {fls: NAV}", "channels.fls: must differ from channels.nav"},
        {"ps: {range_max: .inf}", "ps.range_max"},
        {"ps_selection: {min_range: .nan}", "ps_selection.min_range"},
        {"map: {nx: 0}", "map.nx"},
        {"map: {nx: 4096, ny: 4096, nz: 64}", "daemon.memory_budget_mb"},
        {"segmentation: {max_objects: 0}", "segmentation.max_objects"},
        {"nav: {timeline_confirm: 0}", "nav.timeline_confirm"},
    };
    for (const auto& [yaml, key] : cases) {
        const std::string path = writeTemp(yaml + "\n");
        try {
            (void)loadDaemonConfig(path);
            ADD_FAILURE() << "accepted: " << yaml;
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(key), std::string::npos) << yaml << " -> " << what;
            EXPECT_NE(what.find(path), std::string::npos) << what;
        }
        std::remove(path.c_str());
    }
    const std::string ok = writeTemp("daemon: {segment_period_s: 3600}\n");
    EXPECT_NO_THROW((void)loadDaemonConfig(ok));
    std::remove(ok.c_str());
}

// segmentation.fls_above_seabed_min_votes, when absent, follows the update
// model: the fewest full-intensity FLS votes that alone reach the occupied
// threshold (docs/mapper-config.md). Given, it is taken as it is; out of
// range it is refused by name.
TEST(DaemonConfigValidation, TheAboveSeabedVoteThresholdIsDerivedFromTheUpdateModel) {
    auto minVotes = [](const std::string& yaml) {
        const std::string path = writeTemp(yaml + "\n");
        const int n = loadDaemonConfig(path).mapper.segmentation.fls_above_seabed_min_votes;
        std::remove(path.c_str());
        return n;
    };
    EXPECT_EQ(minVotes("daemon: {segment_period_s: 2}"), 4);            // ceil(0.847 / (0.3 x 0.847))
    EXPECT_EQ(minVotes("update: {alpha_fls: 0.6}"), 2);                  // ceil(1 / 0.6)
    EXPECT_EQ(minVotes("segmentation: {occupied_probability: 0.9}"), 9);  // ceil(2.197 / 0.254)
    EXPECT_EQ(minVotes("segmentation: {fls_above_seabed_min_votes: 0}"), 0);
    EXPECT_EQ(minVotes("segmentation: {fls_above_seabed_min_votes: 7}"), 7);
    const std::string bad = writeTemp("segmentation: {fls_above_seabed_min_votes: 256}\n");
    try {
        (void)loadDaemonConfig(bad);
        ADD_FAILURE() << "accepted 256";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("segmentation.fls_above_seabed_min_votes"), std::string::npos) << e.what();
    }
    std::remove(bad.c_str());
}

// segmentation.fls_votes_per_ps_crossing, when absent, follows the update
// model too: a crossing's weakest carve (the far end of its ray, Eq. 13) over a
// full-intensity FLS vote (Eq. 6). Given, it is taken as it is.
TEST(DaemonConfigValidation, TheVotesPerPsCrossingAreDerivedFromTheUpdateModel) {
    auto perCrossing = [](const std::string& yaml) {
        const std::string path = writeTemp(yaml + "\n");
        const double n = loadDaemonConfig(path).mapper.segmentation.fls_votes_per_ps_crossing;
        std::remove(path.c_str());
        return n;
    };
    EXPECT_NEAR(perCrossing("daemon: {segment_period_s: 2}"), 1.386 * std::exp(-0.5) / (0.3 * 0.847), 0.005);  // 3.31
    EXPECT_NEAR(perCrossing("update: {alpha_ps: 0}"), 1.386 / (0.3 * 0.847), 0.01);
    EXPECT_NEAR(perCrossing("update: {alpha_fls: 0.6}"), 3.31 / 2, 0.005);
    EXPECT_EQ(perCrossing("segmentation: {fls_votes_per_ps_crossing: 0}"), 0.0);
    EXPECT_EQ(perCrossing("segmentation: {fls_votes_per_ps_crossing: 2.5}"), 2.5);
}
