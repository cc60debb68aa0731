// libFuzzer harness for LcmLogReader (apps/common/lcm_log_reader.hpp): the
// first three bytes pick the limits (max data length, max channel length,
// read-ahead), the rest is the log. The in-memory reader and the file reader
// must return the same events and counts, every event must lie inside the
// input where it says, and the byte accounting must add up; any difference
// is a finding (trap). ASan + UBSan catch the rest. Build: docs/robustness.md.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fuzz_util.hpp"
#include "lcm_log_reader.hpp"

namespace {
#define SF_CHECK(c) \
    do {            \
        if (!(c)) __builtin_trap(); \
    } while (0)

struct Seen {
    sonarfusion::LcmLogEvent ev;
    std::size_t channel_off, data_off;  // where the pointers point, relative to the log
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    const std::size_t max_data = std::size_t{data[0]} * 33;  // 0 .. 8415
    const std::size_t max_channel = data[1] < 192 ? 255 : data[1] % 64;  // 0 .. 63 sometimes
    const std::size_t read_ahead = data[2] % 4 == 0 ? 0 : std::size_t{data[2]} * 5;
    const uint8_t* log = data + 3;
    const std::size_t n = size - 3;

    static std::vector<Seen> seen;
    seen.clear();
    sonarfusion::LcmLogReader mem(log, n, max_data, max_channel);
    SF_CHECK(mem.good());
    sonarfusion::LcmLogEvent ev;
    int64_t used = 0, last_end = 0;
    while (mem.next(ev)) {
        SF_CHECK(ev.file_offset >= last_end);
        SF_CHECK(ev.size <= max_data && !ev.channel.empty() && ev.channel.size() <= max_channel);
        const std::size_t ch_off = static_cast<std::size_t>(reinterpret_cast<const uint8_t*>(ev.channel.data()) - log);
        const std::size_t data_off = static_cast<std::size_t>(ev.data - log);
        SF_CHECK(ch_off == static_cast<std::size_t>(ev.file_offset) + 28);
        SF_CHECK(data_off == ch_off + ev.channel.size());
        SF_CHECK(data_off + ev.size <= n);
        SF_CHECK(std::memcmp(log + ev.file_offset, "\xED\xA1\xDA\x01", 4) == 0);
        last_end = static_cast<int64_t>(data_off + ev.size);
        used += 28 + static_cast<int64_t>(ev.channel.size() + ev.size);
        seen.push_back({ev, ch_off, data_off});
    }
    SF_CHECK(!mem.next(ev));
    const sonarfusion::LcmLogStats s = mem.stats();
    SF_CHECK(s.events == static_cast<int64_t>(seen.size()));
    SF_CHECK(used + s.skipped_bytes == static_cast<int64_t>(n));
    SF_CHECK(s.truncated_bytes <= s.skipped_bytes && (s.truncated_bytes > 0) == s.truncated_tail);
    SF_CHECK(mem.lostData() == (s.damaged_regions > 0 || s.truncated_tail));

    // The file reader, through its window, must agree exactly.
    sonarfusion::LcmLogReader file(sffuzz::asFile(log, n), max_data, max_channel, read_ahead);
    SF_CHECK(file.good());
    std::size_t i = 0;
    while (file.next(ev)) {
        SF_CHECK(i < seen.size());
        const Seen& m = seen[i++];
        SF_CHECK(ev.file_offset == m.ev.file_offset && ev.event_number == m.ev.event_number &&
                 ev.utime == m.ev.utime && ev.channel == m.ev.channel && ev.size == m.ev.size);
        SF_CHECK(ev.size == 0 || std::memcmp(ev.data, log + m.data_off, ev.size) == 0);
    }
    SF_CHECK(i == seen.size());
    const sonarfusion::LcmLogStats& f = file.stats();
    SF_CHECK(f.events == s.events && f.damaged_regions == s.damaged_regions && f.skipped_bytes == s.skipped_bytes &&
             f.truncated_tail == s.truncated_tail && f.truncated_bytes == s.truncated_bytes &&
             f.oversized_events == s.oversized_events);
    return 0;
}
