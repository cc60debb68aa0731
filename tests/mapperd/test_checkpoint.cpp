// Checkpoints (issue 10): a node restored from a checkpoint goes on exactly as
// the node that wrote it, and a damaged, cut or foreign file is a clear error.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>

#include "checkpoint.hpp"
#include "mapper_node.hpp"
#include "node_test_util.hpp"

using namespace sonarfusion;
using sonarfusion::test::send;

namespace {
// NAV at 50 Hz and PS pings between, with seabed echoes and, in the middle, a
// 0.5 m rise: enough for the detector to anchor the map part way.
void stream(MapperNode& node, int from, int to) {
    const MapperConfig& c = node.mapper().config();
    for (int i = from; i < to; ++i) {
        const int64_t t = 1000000 + int64_t{i} * 20000;
        nav_state_t n{};
        n.utime = t;
        n.seq = i;
        n.position_ned[0] = 0.01 * i - 4.0;
        n.position_ned[2] = 20.0 - 3.12;
        send(node, "NAV", n);
        ps_ping_t p = sonarfusion::test::psPing(c, t + 10000, i, (i % 21 - 10) * 2.0 * kDegToRad);
        const bool rise = i > 350 && i < 450 && i % 21 > 7 && i % 21 < 13;
        const int bin = rise ? 200 : 242 + (i % 3);
        p.intensity[bin] = static_cast<int8_t>(-56);
        send(node, "PS", p);
    }
}

std::vector<uint8_t> state(const MapperNode& node) {
    std::vector<uint8_t> buf(node.stateBytesBound());
    StateWriter w(buf.data(), buf.size());
    node.saveState(w);
    EXPECT_FALSE(w.overflow());
    buf.resize(w.size());
    return buf;
}

std::string tempPath(const char* name) { return "/tmp/sf_ckpt_" + std::to_string(getpid()) + "_" + name; }
}  // namespace

TEST(Checkpoint, ARestoredNodeGoesOnExactlyLikeTheOriginal) {
    DaemonConfig cfg;
    // The state carries the count of messages over the time budget, which
    // depends on the machine's load, not on the data: with a budget no message
    // can exceed, the two nodes must agree byte for byte (this test failed
    // under load before).
    cfg.budget_us = 1e15;
    MapperNode a(cfg, {});
    stream(a, 0, 400);
    // A ping waiting for NAV is part of the state too.
    const std::vector<uint8_t> mid = state(a);
    ASSERT_GT(a.pendingCount(), 0);

    MapperNode b(cfg, {});
    StateReader r(mid.data(), mid.size());
    ASSERT_TRUE(b.loadState(r));
    EXPECT_EQ(state(b), mid);

    stream(a, 400, 800);
    stream(b, 400, 800);
    a.flush(true);
    b.flush(true);
    EXPECT_EQ(state(a), state(b));
    EXPECT_EQ(a.mapper().map().logOddsData(), b.mapper().map().logOddsData());
    EXPECT_EQ(a.mapper().counters().ps_used, b.mapper().counters().ps_used);
}

TEST(Checkpoint, StateFromAnotherConfigOrCutShortIsRefused) {
    DaemonConfig cfg;
    MapperNode a(cfg, {});
    stream(a, 0, 100);
    std::vector<uint8_t> s = state(a);
    DaemonConfig other = cfg;
    other.mapper.map.nx = 90;
    MapperNode b(other, {});
    StateReader r(s.data(), s.size());
    EXPECT_FALSE(b.loadState(r));
    for (std::size_t cut : {std::size_t{0}, std::size_t{7}, s.size() / 2, s.size() - 1}) {
        MapperNode c(cfg, {});
        StateReader rc(s.data(), cut);
        EXPECT_FALSE(c.loadState(rc)) << cut;
    }
}

TEST(Checkpoint, FileRoundTripsAndEveryDamageIsAClearError) {
    DaemonConfig cfg;
    MapperNode a(cfg, {});
    stream(a, 0, 200);
    const std::string path = tempPath("file");
    const uint64_t fp = configFingerprint(cfg);
    {
        CheckpointWriter w(path, a.stateBytesBound(), fp);
        ASSERT_TRUE(w.submit([&](StateWriter& sw) { a.saveState(sw); }));
        w.drain();
        EXPECT_EQ(w.written(), 1);
    }
    EXPECT_EQ(readCheckpoint(path, fp), state(a));
    EXPECT_NE(access((path + ".tmp").c_str(), F_OK), 0);  // no temporary left

    std::ifstream in(path, std::ios::binary);
    const std::vector<char> good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto expectError = [&](std::vector<char> bytes, const std::string& words, uint64_t fingerprint) {
        std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<long>(bytes.size()));
        try {
            (void)readCheckpoint(path, fingerprint);
            ADD_FAILURE() << "accepted: " << words;
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    std::vector<char> flipped = good;
    flipped[flipped.size() / 2] ^= 0x10;
    expectError(flipped, "checksum", fp);
    expectError(std::vector<char>(good.begin(), good.begin() + static_cast<long>(good.size() - 100)), "size", fp);
    expectError(std::vector<char>(good.begin(), good.begin() + 10), "too short", fp);
    std::vector<char> magic = good;
    magic[0] = 'X';
    expectError(magic, "magic", fp);
    DaemonConfig other = cfg;
    other.mapper.map.resolution = 0.05;
    expectError(good, "another config", configFingerprint(other));
    std::remove(path.c_str());
    expectError({}, "too short", fp);
    std::remove(path.c_str());
    try {
        (void)readCheckpoint(path, fp);
        ADD_FAILURE() << "a missing file was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
    }
}

TEST(Checkpoint, AFailedWriteKeepsTheLastGoodFileAndLeavesNoTemporary) {
    DaemonConfig cfg;
    MapperNode a(cfg, {});
    stream(a, 0, 50);
    CheckpointWriter w("/nonexistent-folder/ckpt", a.stateBytesBound(), configFingerprint(cfg));
    EXPECT_TRUE(w.submit([&](StateWriter& sw) { a.saveState(sw); }));
    w.drain();
    EXPECT_EQ(w.failed(), 1);
    EXPECT_EQ(w.written(), 0);
    // Too small a buffer is a counted failure, not an overflow.
    CheckpointWriter small(tempPath("small"), 16, configFingerprint(cfg));
    EXPECT_FALSE(small.submit([&](StateWriter& sw) { a.saveState(sw); }));
    EXPECT_EQ(small.failed(), 1);
}
