// LcmLogReader: valid logs read exactly as liblcm reads them; damaged logs
// give back exactly the events the damage left whole, count the damage, and
// never read out of bounds or allocate from a length in the file. Every case
// runs through the in-memory reader and the file reader (with read-ahead 0,
// an odd small one and the default), which must agree byte for byte.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "lcm_log_reader.hpp"
#include "temp_dir.hpp"

using namespace sonarfusion;

namespace {
constexpr std::size_t kMaxData = 4096;

struct Ev {
    int64_t num = 0, utime = 0;
    std::string channel;
    std::vector<uint8_t> data;
    bool operator==(const Ev& o) const {
        return num == o.num && utime == o.utime && channel == o.channel && data == o.data;
    }
};

std::ostream& operator<<(std::ostream& os, const Ev& e) {
    return os << "{#" << e.num << " t=" << e.utime << " " << e.channel << " " << e.data.size() << " B}";
}

void putBe(std::vector<uint8_t>& b, uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void setBe32(std::vector<uint8_t>& b, std::size_t off, uint32_t v) {
    for (int i = 0; i < 4; ++i) b[off + i] = static_cast<uint8_t>(v >> (8 * (3 - i)));
}

// A log written by hand, with where each event starts.
struct Log {
    std::vector<Ev> events;
    std::vector<uint8_t> bytes;
    std::vector<std::size_t> start;  // start[i]: offset of event i; start.back(): end of the log
    std::size_t size(std::size_t i) const { return start[i + 1] - start[i]; }
};

Log encode(const std::vector<Ev>& evs) {
    Log log;
    log.events = evs;
    for (const Ev& e : evs) {
        log.start.push_back(log.bytes.size());
        putBe(log.bytes, LcmLogReader::kSyncWord, 4);
        putBe(log.bytes, static_cast<uint64_t>(e.num), 8);
        putBe(log.bytes, static_cast<uint64_t>(e.utime), 8);
        putBe(log.bytes, e.channel.size(), 4);
        putBe(log.bytes, e.data.size(), 4);
        log.bytes.insert(log.bytes.end(), e.channel.begin(), e.channel.end());
        log.bytes.insert(log.bytes.end(), e.data.begin(), e.data.end());
    }
    log.start.push_back(log.bytes.size());
    return log;
}

// Bytes below 0xED: never the first byte of a sync word, so a damaged log's
// only sync words are the events' own.
std::vector<uint8_t> noise(std::mt19937& rng, std::size_t n) {
    std::uniform_int_distribution<int> byte(0, 0xEC);
    std::vector<uint8_t> v(n);
    for (uint8_t& b : v) b = static_cast<uint8_t>(byte(rng));
    return v;
}

std::vector<Ev> makeEvents(int n, uint32_t seed = 1) {
    std::mt19937 rng(seed);
    static const char* const kCh[] = {"NAV", "FLS", "PS", "MAPPER_STATUS"};
    std::vector<Ev> evs;
    for (int i = 0; i < n; ++i) {
        Ev e;
        e.num = i;
        e.utime = 1'700'000'000'000'000 + 100'000 * i;
        e.channel = kCh[i % 4];
        const std::size_t len = i == 3 ? 0 : std::uniform_int_distribution<std::size_t>(1, 1500)(rng);
        e.data = noise(rng, len);
        evs.push_back(e);
    }
    return evs;
}

// Each test's own folder (temp_dir.hpp).
class TempDir : public test::TempDir {
public:
    TempDir() : test::TempDir("sf-lcmlog-test") {}
};

std::string writeFile(const TempDir& dir, const std::vector<uint8_t>& bytes, const std::string& name = "log") {
    const std::string p = dir.file(name);
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return p;
}

struct Result {
    std::vector<Ev> events;
    std::vector<int64_t> offsets;
    LcmLogStats stats;
};

Result readAll(LcmLogReader& r) {
    Result res;
    LcmLogEvent ev;
    while (r.next(ev)) {
        Ev e;
        e.num = ev.event_number;
        e.utime = ev.utime;
        e.channel = std::string(ev.channel);
        e.data.assign(ev.data, ev.data + ev.size);
        res.events.push_back(std::move(e));
        res.offsets.push_back(ev.file_offset);
    }
    LcmLogEvent more;
    EXPECT_FALSE(r.next(more)) << "next() after the end must stay false";
    res.stats = r.stats();
    EXPECT_EQ(r.lostData(), res.stats.damaged_regions > 0 || res.stats.truncated_tail);
    return res;
}

// Reads `bytes` every way, checks the ways agree and the byte accounting adds
// up, and returns the in-memory result.
Result readEveryWay(const std::vector<uint8_t>& bytes, std::size_t max_data = kMaxData) {
    LcmLogReader mem(bytes.data(), bytes.size(), max_data);
    EXPECT_TRUE(mem.good());
    Result ref = readAll(mem);
    int64_t used = 0;
    for (const Ev& e : ref.events) used += 28 + static_cast<int64_t>(e.channel.size() + e.data.size());
    EXPECT_EQ(used + ref.stats.skipped_bytes, static_cast<int64_t>(bytes.size()));
    EXPECT_EQ(ref.stats.events, static_cast<int64_t>(ref.events.size()));
    TempDir dir;
    const std::string path = writeFile(dir, bytes);
    for (std::size_t ra : {std::size_t{0}, std::size_t{13}, LcmLogReader::kDefaultReadAhead}) {
        LcmLogReader file(path, max_data, 255, ra);
        EXPECT_TRUE(file.good());
        const Result r = readAll(file);
        EXPECT_EQ(r.events, ref.events) << "read-ahead " << ra;
        EXPECT_EQ(r.offsets, ref.offsets) << "read-ahead " << ra;
        EXPECT_EQ(r.stats.damaged_regions, ref.stats.damaged_regions) << "read-ahead " << ra;
        EXPECT_EQ(r.stats.skipped_bytes, ref.stats.skipped_bytes) << "read-ahead " << ra;
        EXPECT_EQ(r.stats.truncated_tail, ref.stats.truncated_tail) << "read-ahead " << ra;
        EXPECT_EQ(r.stats.truncated_bytes, ref.stats.truncated_bytes) << "read-ahead " << ra;
        EXPECT_EQ(r.stats.oversized_events, ref.stats.oversized_events) << "read-ahead " << ra;
    }
    return ref;
}

std::vector<Ev> without(const std::vector<Ev>& evs, std::initializer_list<std::size_t> drop) {
    std::vector<Ev> out;
    for (std::size_t i = 0; i < evs.size(); ++i)
        if (std::find(drop.begin(), drop.end(), i) == drop.end()) out.push_back(evs[i]);
    return out;
}

void expectDamage(const Result& r, const std::vector<Ev>& expected, int64_t regions, int64_t skipped) {
    EXPECT_EQ(r.events, expected);
    EXPECT_EQ(r.stats.damaged_regions, regions);
    EXPECT_EQ(r.stats.skipped_bytes, skipped);
    EXPECT_FALSE(r.stats.truncated_tail);
}

constexpr std::size_t kChannelLenOff = 20, kDataLenOff = 24;
}  // namespace

TEST(LcmLogReader, ValidLogReadsLikeLiblcmByteForByte) {
    TempDir dir;
    const std::vector<Ev> evs = makeEvents(40);
    const std::string path = dir.file("lcm.lcmlog");
    {
        lcm::LogFile w(path, "w");
        ASSERT_TRUE(w.good());
        for (const Ev& e : evs) {
            lcm::LogEvent le;
            le.eventnum = e.num;  // liblcm numbers the events itself, from 0, as makeEvents does
            le.timestamp = e.utime;
            le.channel = e.channel;
            le.datalen = static_cast<int32_t>(e.data.size());
            le.data = const_cast<uint8_t*>(e.data.data());
            ASSERT_EQ(w.writeEvent(&le), 0);
        }
    }
    // Our hand encoder writes exactly what liblcm writes.
    std::ifstream f(path, std::ios::binary);
    const std::vector<uint8_t> written((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_EQ(written, encode(evs).bytes);

    std::vector<Ev> by_lcm;
    lcm::LogFile r(path, "r");
    ASSERT_TRUE(r.good());
    while (const lcm::LogEvent* le = r.readNextEvent()) {
        Ev e;
        e.num = le->eventnum;
        e.utime = le->timestamp;
        e.channel = le->channel;
        const auto* d = static_cast<const uint8_t*>(le->data);
        e.data.assign(d, d + le->datalen);
        by_lcm.push_back(std::move(e));
    }
    ASSERT_EQ(by_lcm.size(), evs.size());

    LcmLogReader ours(path, kMaxData);
    ASSERT_TRUE(ours.good());
    const Result res = readAll(ours);
    EXPECT_EQ(res.events, by_lcm);
    EXPECT_EQ(res.stats.events, 40);
    EXPECT_FALSE(ours.lostData());
    EXPECT_EQ(res.stats.skipped_bytes, 0);
    EXPECT_EQ(readEveryWay(written).events, by_lcm);
}

TEST(LcmLogReader, EventOffsetsAndLimitsAreExact) {
    const Log log = encode(makeEvents(6));
    const Result r = readEveryWay(log.bytes);
    ASSERT_EQ(r.events.size(), 6u);
    for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(r.offsets[i], static_cast<int64_t>(log.start[i]));
    EXPECT_EQ(r.events[3].data.size(), 0u);  // an empty payload is valid
    // An event exactly at max_data_len is accepted; one byte over, the
    // well-formed event is skipped unread (oversized), which is not damage.
    std::size_t largest = 0, which = 0;
    for (std::size_t i = 0; i < log.events.size(); ++i)
        if (log.events[i].data.size() > largest) largest = log.events[i].data.size(), which = i;
    EXPECT_EQ(readEveryWay(log.bytes, largest).events.size(), 6u);
    const Result over = readEveryWay(log.bytes, largest - 1);
    EXPECT_EQ(over.events, without(log.events, {which}));
    EXPECT_EQ(over.stats.oversized_events, 1);
    EXPECT_EQ(over.stats.damaged_regions, 0);
    EXPECT_EQ(over.stats.skipped_bytes, static_cast<int64_t>(log.size(which)));
}

TEST(LcmLogReader, WellFormedEventsLargerThanTheLimitAreSkippedUnread) {
    // An lcm-logger recording holds every channel, e.g. another program's
    // large map snapshots: skipped without reading or allocating, not damage.
    std::vector<Ev> evs = makeEvents(8);
    std::mt19937 rng(5);
    evs[2].data = noise(rng, 3 * kMaxData);
    evs[7].data = noise(rng, kMaxData + 1);  // the last one, ending at the end of the file
    const Log log = encode(evs);
    const Result r = readEveryWay(log.bytes);
    EXPECT_EQ(r.events, without(evs, {2, 7}));
    EXPECT_EQ(r.stats.oversized_events, 2);
    EXPECT_EQ(r.stats.damaged_regions, 0);
    EXPECT_FALSE(r.stats.truncated_tail);
    EXPECT_EQ(r.stats.skipped_bytes, static_cast<int64_t>(log.size(2) + log.size(7)));
    LcmLogReader mem(log.bytes.data(), log.bytes.size(), kMaxData);
    LcmLogEvent ev;
    while (mem.next(ev)) {
    }
    EXPECT_FALSE(mem.lostData());
    // Cut inside an oversized last event: longer than the limit and the file, damage.
    const std::vector<uint8_t> cut(log.bytes.begin(), log.bytes.end() - 10);
    const Result c = readEveryWay(cut);
    EXPECT_EQ(c.events, without(evs, {2, 7}));
    EXPECT_EQ(c.stats.damaged_regions, 1);
}

TEST(LcmLogReader, EmptyFileIsCleanAndMissingFileIsNotGood) {
    const Result r = readEveryWay({});
    EXPECT_TRUE(r.events.empty());
    EXPECT_EQ(r.stats.damaged_regions, 0);
    EXPECT_FALSE(r.stats.truncated_tail);
    LcmLogReader missing("/nonexistent/sf-test.lcmlog", kMaxData);
    EXPECT_FALSE(missing.good());
    LcmLogEvent ev;
    EXPECT_FALSE(missing.next(ev));
    TempDir dir;
    LcmLogReader directory(dir.file(""), kMaxData);
    EXPECT_FALSE(directory.good()) << "a directory is not a log";
}

TEST(LcmLogReader, OnlyGarbageIsOneDamagedRegion) {
    std::mt19937 rng(7);
    for (std::size_t n : {1u, 3u, 27u, 28u, 5000u}) {
        const std::vector<uint8_t> junk = noise(rng, n);
        const Result r = readEveryWay(junk);
        EXPECT_TRUE(r.events.empty());
        EXPECT_EQ(r.stats.damaged_regions, 1) << n;
        EXPECT_EQ(r.stats.skipped_bytes, static_cast<int64_t>(n));
    }
    // Garbage full of sync words, each with a hostile header, is still nothing.
    std::vector<uint8_t> syncs;
    for (int i = 0; i < 500; ++i) {
        putBe(syncs, LcmLogReader::kSyncWord, 4);
        putBe(syncs, static_cast<uint64_t>(i), 8);
        putBe(syncs, 0, 8);
        putBe(syncs, static_cast<uint64_t>(i % 7), 4);   // channel lengths 0..6
        putBe(syncs, static_cast<uint64_t>(i * 997), 4);  // data lengths past the next sync word
    }
    const Result r = readEveryWay(syncs);
    EXPECT_TRUE(r.events.empty());
    EXPECT_EQ(r.stats.skipped_bytes, static_cast<int64_t>(syncs.size()));
}

TEST(LcmLogReader, BadSyncWordCostsOnlyThatEvent) {
    const Log log = encode(makeEvents(10));
    for (std::size_t k : {0u, 4u, 9u}) {
        for (std::size_t byte = 0; byte < 4; ++byte) {
            std::vector<uint8_t> b = log.bytes;
            b[log.start[k] + byte] ^= 0x5a;
            SCOPED_TRACE("event " + std::to_string(k) + " sync byte " + std::to_string(byte));
            expectDamage(readEveryWay(b), without(log.events, {k}), 1, static_cast<int64_t>(log.size(k)));
        }
    }
}

TEST(LcmLogReader, GarbageBetweenEvents) {
    const Log log = encode(makeEvents(10));
    std::mt19937 rng(3);
    // Before the first event: only the garbage is lost.
    for (std::size_t n : {1u, 5u, 28u, 1000u}) {
        std::vector<uint8_t> b = noise(rng, n);
        b.insert(b.end(), log.bytes.begin(), log.bytes.end());
        expectDamage(readEveryWay(b), log.events, 1, static_cast<int64_t>(n));
    }
    // After event k: the event before the garbage cannot be told from one
    // whose data length was shortened (both are followed by bytes that are not
    // a sync word), so the rule "followed by a sync word" drops it with the
    // garbage; every other event comes back.
    for (std::size_t k : {0u, 4u, 9u}) {
        for (std::size_t n : {1u, 4u, 31u, 1000u}) {
            std::vector<uint8_t> b = log.bytes;
            const std::vector<uint8_t> junk = noise(rng, n);
            b.insert(b.begin() + static_cast<std::ptrdiff_t>(log.start[k + 1]), junk.begin(), junk.end());
            SCOPED_TRACE("after event " + std::to_string(k) + ", " + std::to_string(n) + " bytes");
            expectDamage(readEveryWay(b), without(log.events, {k}), 1, static_cast<int64_t>(log.size(k) + n));
        }
    }
    // Garbage that holds a sync word with a plausible header resynchronises on the real events.
    std::vector<uint8_t> b = log.bytes;
    std::vector<uint8_t> junk = noise(rng, 40);
    junk[10] = 0xED, junk[11] = 0xA1, junk[12] = 0xDA, junk[13] = 0x01;
    b.insert(b.begin() + static_cast<std::ptrdiff_t>(log.start[5]), junk.begin(), junk.end());
    const Result r = readEveryWay(b);
    EXPECT_EQ(r.events, without(log.events, {4}));
    EXPECT_EQ(r.stats.skipped_bytes, static_cast<int64_t>(log.size(4) + 40));
}

TEST(LcmLogReader, BadChannelLengths) {
    const Log log = encode(makeEvents(10));
    for (std::size_t k : {0u, 5u, 9u}) {
        for (int32_t cl : {0, -1, 100000, 256, INT32_MIN, INT32_MAX}) {
            std::vector<uint8_t> b = log.bytes;
            setBe32(b, log.start[k] + kChannelLenOff, static_cast<uint32_t>(cl));
            SCOPED_TRACE("event " + std::to_string(k) + " channel length " + std::to_string(cl));
            expectDamage(readEveryWay(b), without(log.events, {k}), 1, static_cast<int64_t>(log.size(k)));
        }
    }
}

TEST(LcmLogReader, HostileDataLengths) {
    // The lengths that crash (0x7fffffff: SIGSEGV in lcm_eventlog_read_next_event)
    // or stop liblcm's reader.
    const Log log = encode(makeEvents(10));
    for (std::size_t k : {0u, 5u}) {
        for (int32_t dl : {-1, INT32_MAX, 1 << 30, INT32_MIN, static_cast<int32_t>(kMaxData + 1)}) {
            std::vector<uint8_t> b = log.bytes;
            setBe32(b, log.start[k] + kDataLenOff, static_cast<uint32_t>(dl));
            SCOPED_TRACE("event " + std::to_string(k) + " data length " + std::to_string(dl));
            expectDamage(readEveryWay(b), without(log.events, {k}), 1, static_cast<int64_t>(log.size(k)));
        }
    }
    // The same in the last event: nothing after it, still damage (not a truncated tail).
    for (int32_t dl : {-1, INT32_MAX, 1 << 30}) {
        std::vector<uint8_t> b = log.bytes;
        setBe32(b, log.start[9] + kDataLenOff, static_cast<uint32_t>(dl));
        expectDamage(readEveryWay(b), without(log.events, {9}), 1, static_cast<int64_t>(log.size(9)));
    }
}

TEST(LcmLogReader, DataLengthChangedToAnotherInRangeValue) {
    const Log log = encode(makeEvents(10));
    for (std::size_t k : {0u, 2u, 5u, 8u}) {
        const int64_t dl = static_cast<int64_t>(log.events[k].data.size());
        for (int64_t changed : {dl + 1, dl - 1, dl + 4, dl - 4, dl + 37, int64_t{0}, int64_t{kMaxData}}) {
            if (changed < 0 || changed == dl || changed > static_cast<int64_t>(kMaxData)) continue;
            std::vector<uint8_t> b = log.bytes;
            setBe32(b, log.start[k] + kDataLenOff, static_cast<uint32_t>(changed));
            SCOPED_TRACE("event " + std::to_string(k) + " data length " + std::to_string(dl) + " -> " +
                         std::to_string(changed));
            expectDamage(readEveryWay(b), without(log.events, {k}), 1, static_cast<int64_t>(log.size(k)));
        }
    }
    // The last event shortened: the rest of its data is not a sync word: damage.
    {
        std::vector<uint8_t> b = log.bytes;
        setBe32(b, log.start[9] + kDataLenOff, static_cast<uint32_t>(log.events[9].data.size() - 10));
        expectDamage(readEveryWay(b), without(log.events, {9}), 1, static_cast<int64_t>(log.size(9)));
    }
    // The last event lengthened past the end of the file: a cut tail, as far as anyone can tell.
    {
        std::vector<uint8_t> b = log.bytes;
        setBe32(b, log.start[9] + kDataLenOff, static_cast<uint32_t>(log.events[9].data.size() + 10));
        const Result r = readEveryWay(b);
        EXPECT_EQ(r.events, without(log.events, {9}));
        EXPECT_TRUE(r.stats.truncated_tail);
        EXPECT_EQ(r.stats.damaged_regions, 0);
    }
}

TEST(LcmLogReader, CutAtEveryOffsetInsideTheLastEvent) {
    const Log log = encode(makeEvents(6));
    const std::size_t last = 5;
    const std::vector<Ev> whole = without(log.events, {last});
    for (std::size_t cut = 1; cut < log.size(last); ++cut) {
        const std::vector<uint8_t> b(log.bytes.begin(),
                                     log.bytes.begin() + static_cast<std::ptrdiff_t>(log.start[last] + cut));
        SCOPED_TRACE("cut " + std::to_string(cut) + " bytes into the last event");
        const Result r = readEveryWay(b);
        ASSERT_EQ(r.events, whole);
        ASSERT_TRUE(r.stats.truncated_tail);
        ASSERT_EQ(r.stats.damaged_regions, 0);
        ASSERT_EQ(r.stats.skipped_bytes, static_cast<int64_t>(cut));
        ASSERT_EQ(r.stats.truncated_bytes, static_cast<int64_t>(cut));
    }
}

TEST(LcmLogReader, DamageThenCutTail) {
    // A damaged event in the middle and a cut last event: both counted, each for what it is.
    const Log log = encode(makeEvents(8));
    std::vector<uint8_t> b(log.bytes.begin(), log.bytes.begin() + static_cast<std::ptrdiff_t>(log.start[7] + 50));
    setBe32(b, log.start[3] + kChannelLenOff, 0);
    const Result r = readEveryWay(b);
    EXPECT_EQ(r.events, without(log.events, {3, 7}));
    EXPECT_EQ(r.stats.damaged_regions, 1);
    EXPECT_TRUE(r.stats.truncated_tail);
    EXPECT_EQ(r.stats.truncated_bytes, 50);
    EXPECT_EQ(r.stats.skipped_bytes, static_cast<int64_t>(log.size(3) + 50));
}

TEST(LcmLogReader, RandomDamageGivesBackOnlyWrittenEventsInOrder) {
    // Damaged sync words, garbage spliced between events and a random cut,
    // several at once: every event that comes back is one that was written,
    // in order, and the byte accounting adds up (readEveryWay). (Flipped data
    // bytes are not in this test: a log has no checksum, so nobody can see
    // them; fuzz_lcm_log throws arbitrary bytes at the reader instead.)
    const Log log = encode(makeEvents(12, 9));
    std::mt19937 rng(11);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<uint8_t> b = log.bytes;
        std::vector<std::size_t> starts(log.start.begin(), log.start.end() - 1);
        const int n = std::uniform_int_distribution<int>(1, 4)(rng);
        for (int i = 0; i < n; ++i) {
            const std::size_t k = std::uniform_int_distribution<std::size_t>(0, starts.size() - 1)(rng);
            if (rng() % 2) {
                b[starts[k] + rng() % 4] ^= static_cast<uint8_t>(1 + rng() % 255);
            } else {
                const std::vector<uint8_t> junk = noise(rng, 1 + rng() % 60);
                b.insert(b.begin() + static_cast<std::ptrdiff_t>(starts[k]), junk.begin(), junk.end());
                for (std::size_t j = k; j < starts.size(); ++j) starts[j] += junk.size();
            }
        }
        if (trial % 3 == 0) b.resize(std::uniform_int_distribution<std::size_t>(0, b.size())(rng));
        const Result r = readEveryWay(b);
        std::size_t j = 0;
        for (const Ev& e : r.events) {
            while (j < log.events.size() && !(log.events[j] == e)) ++j;
            ASSERT_LT(j, log.events.size()) << "trial " << trial << ": an event that was never written: " << e;
            ++j;
        }
    }
}
