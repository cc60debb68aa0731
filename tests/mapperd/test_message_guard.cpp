// Hostile bytes must be refused before lcm-gen's decode sees them, and nothing
// the node is fed may crash it or touch the map.
#include <gtest/gtest.h>

#include <random>

#include "mapper_node.hpp"
#include "node_test_util.hpp"
#include "message_guard.hpp"

using namespace sonarfusion;
using sonarfusion::test::encode;

namespace {
fls_image_t validFls() {
    fls_image_t m{};
    m.utime = 1;
    m.num_beams = 96;
    m.beam_bearing.assign(96, 0.0f);
    m.num_ranges = 512;
    m.row_range.assign(512, 1.0f);
    m.data_size = 512 * 96;
    m.data.assign(512 * 96, 0);
    return m;
}

// Overwrites the big-endian int32 at `off`.
void putInt32(std::vector<uint8_t>& b, std::size_t off, int32_t v) {
    const uint32_t u = static_cast<uint32_t>(v);
    b[off] = u >> 24, b[off + 1] = (u >> 16) & 0xff, b[off + 2] = (u >> 8) & 0xff, b[off + 3] = u & 0xff;
}
}  // namespace

TEST(MessageGuard, AcceptsValidMessages) {
    const auto fls = encode(validFls());
    EXPECT_EQ(guard::checkFls(fls.data(), fls.size()), guard::Verdict::Ok);
    ps_ping_t p{};
    p.num_bins = 500;
    p.intensity.assign(500, 0);
    const auto ps = encode(p);
    EXPECT_EQ(guard::checkPs(ps.data(), ps.size()), guard::Verdict::Ok);
    nav_state_t n{};
    const auto nav = encode(n);
    EXPECT_EQ(guard::checkNav(nav.data(), nav.size()), guard::Verdict::Ok);
    EXPECT_EQ(guard::checkNav(fls.data(), fls.size()), guard::Verdict::BadFingerprint);
}

TEST(MessageGuard, RefusesNegativeAndHugeCounts) {
    auto fls = encode(validFls());
    // Offset of num_beams: fingerprint 8, utime 8, seq 8, sensor_name (4 + 1), then 40 bytes of scalars.
    const std::size_t num_beams_at = 8 + 8 + 8 + 5 + 40;
    putInt32(fls, num_beams_at, -5);
    EXPECT_EQ(guard::checkFls(fls.data(), fls.size()), guard::Verdict::BadCount);
    putInt32(fls, num_beams_at, 0x7fffffff);
    EXPECT_EQ(guard::checkFls(fls.data(), fls.size()), guard::Verdict::BadCount);
    putInt32(fls, num_beams_at, 4000);  // plausible count, but the rest no longer adds up
    EXPECT_NE(guard::checkFls(fls.data(), fls.size()), guard::Verdict::Ok);
    auto short_fls = encode(validFls());
    short_fls.resize(num_beams_at + 4 + 100);  // count says 96 floats, 25 are there
    EXPECT_EQ(guard::checkFls(short_fls.data(), short_fls.size()), guard::Verdict::Truncated);
}

TEST(MessageGuard, TruncationsAndRandomBytesNeverCrashTheNode) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    const auto fls = encode(validFls());
    for (std::size_t n = 0; n < fls.size(); n += 97) {
        EXPECT_NE(guard::checkFls(fls.data(), n), guard::Verdict::Ok);
        node.handle("FLS", fls.data(), n);
    }
    std::mt19937 rng(3);
    std::vector<uint8_t> junk(70000);
    for (int trial = 0; trial < 2000; ++trial) {
        const std::size_t n = rng() % junk.size();
        for (std::size_t i = 0; i < n; ++i) junk[i] = static_cast<uint8_t>(rng());
        // Keep a valid fingerprint half the time so the walk goes deep.
        if (trial % 2 == 0 && n >= 8) std::copy(fls.begin(), fls.begin() + 8, junk.begin());
        for (const char* ch : {"NAV", "FLS", "PS"}) node.handle(ch, junk.data(), n);
    }
    node.flush(true);
    EXPECT_GT(node.refusedBytes(), 0);
    for (float l : node.mapper().map().logOddsData()) ASSERT_EQ(l, 0.0f);
}

// Structure-aware mutation: start from valid encodings and flip bytes, cut,
// extend and rewrite array counts. Whatever the guard accepts, lcm-gen's
// decode must take without throwing; whatever it refuses is counted.
TEST(MessageGuard, MutatedValidMessagesAreAcceptedOnlyWhenDecodable) {
    ps_ping_t ps{};
    ps.num_bins = 500;
    ps.intensity.assign(500, 7);
    nav_state_t nav{};
    const std::vector<std::vector<uint8_t>> seeds = {encode(validFls()), encode(ps), encode(nav)};
    const char* channels[] = {"FLS", "PS", "NAV"};
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    std::mt19937 rng(11);
    int accepted = 0, refused = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const int which = trial % 3;
        std::vector<uint8_t> m = seeds[which];
        switch (rng() % 4) {
            case 0:  // flip a few bytes anywhere after the fingerprint
                for (int k = 0; k < 1 + static_cast<int>(rng() % 4); ++k) m[8 + rng() % (m.size() - 8)] ^= static_cast<uint8_t>(1 + rng() % 255);
                break;
            case 1:  // cut
                m.resize(rng() % m.size());
                break;
            case 2:  // extend
                m.resize(m.size() + 1 + rng() % 64, static_cast<uint8_t>(rng()));
                break;
            default:  // rewrite a 4-byte window as a random count
                if (m.size() > 12) putInt32(m, 8 + rng() % (m.size() - 12), static_cast<int32_t>(rng()));
        }
        const guard::Verdict v = which == 0   ? guard::checkFls(m.data(), m.size())
                                 : which == 1 ? guard::checkPs(m.data(), m.size())
                                              : guard::checkNav(m.data(), m.size());
        if (v == guard::Verdict::Ok) {
            ++accepted;
            int rc = -1;
            ASSERT_NO_THROW({
                if (which == 0) rc = fls_image_t{}.decode(m.data(), 0, static_cast<int>(m.size()));
                else if (which == 1) rc = ps_ping_t{}.decode(m.data(), 0, static_cast<int>(m.size()));
                else rc = nav_state_t{}.decode(m.data(), 0, static_cast<int>(m.size()));
            }) << "trial " << trial;
            EXPECT_EQ(rc, static_cast<int>(m.size())) << "the guard accepted bytes decode does not consume exactly";
        } else {
            ++refused;
        }
        node.handle(channels[which], m.data(), m.size());
    }
    node.flush(true);
    EXPECT_GT(accepted, 1000);  // byte flips inside data arrays stay valid messages
    EXPECT_GT(refused, 1000);
    EXPECT_EQ(node.refusedBytes(), refused);
}

TEST(MapperNode, HostileSequenceNumbersSaturateTheGapCounter) {
    DaemonConfig cfg;
    MapperNode node(cfg, {});
    for (int64_t seq : {int64_t{0}, INT64_MAX, int64_t{1}, INT64_MAX}) {
        nav_state_t n{};
        n.seq = seq;
        n.utime = seq;  // hostile time stamps too
        const auto bytes = encode(n);
        node.handle("NAV", bytes.data(), bytes.size());
    }
    EXPECT_EQ(node.seqGaps(0), INT64_MAX);  // saturated, never wrapped negative
}
