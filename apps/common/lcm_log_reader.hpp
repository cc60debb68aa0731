// A reader of LCM log files (the format lcm-logger writes) that survives
// damaged files: it never trusts a length before checking it, never reads
// outside the file, allocates its buffers once (bounded by max_data_len, not
// by what the file claims) and, on damage, resynchronises on the next sync
// word the way lcm-logplayer users expect, counting what it skipped
// (docs/robustness.md, "LCM log files").
//
// Format, every field big-endian, events back to back:
//   uint32 sync word 0xEDA1DA01, int64 event number, int64 utime,
//   int32 channel length, int32 data length, channel bytes, data bytes.
//
// An event is accepted only when its sync word matches, 1 <= channel length
// <= max_channel_len, 0 <= data length <= max_data_len, it lies wholly inside
// the file, and it is followed by the next sync word or by the end of the
// file (this catches a length corrupted to another in-range value). Anything
// else is damage: one damaged region per stretch of bytes skipped up to the
// next event that passes these checks. (One exception to the rule: an event
// followed by a header that is whole but for its sync word, and whose own
// event ends at a sync word, is accepted; so a damaged sync word costs one
// event, not two.) An event whose data length exceeds max_data_len but which
// otherwise passes every check (inside the file, followed by a sync word or the
// end of the file: a well-formed message larger than the caller wants, such
// as another program's map snapshot in an lcm-logger recording) is skipped
// unread and counted in oversized_events; it is not damage. A last event cut short by the end of
// the file is a truncated tail, not damage. Invariant after the last next():
//   sum over events of (28 + channel length + data length) + skipped_bytes == file size.
//
// Usage:
//   sonarfusion::LcmLogReader log(path, largest_message_bytes);
//   if (!log.good()) { /* cannot open */ }
//   sonarfusion::LcmLogEvent ev;
//   while (log.next(ev)) handle(ev.channel, ev.data, ev.size);
//   if (log.lostData()) { /* log.stats(): damaged_regions, skipped_bytes, truncated_tail */ }
//
// ev.channel and ev.data point into the reader's buffer (or, for the
// in-memory constructor, into the caller's bytes) and stay valid until the
// next call to next(). Not thread-safe; one reader per thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sonarfusion {

struct LcmLogEvent {
    int64_t event_number = 0;
    int64_t utime = 0;
    std::string_view channel;
    const uint8_t* data = nullptr;
    std::size_t size = 0;
    int64_t file_offset = 0;  // of the event's sync word
};

struct LcmLogStats {
    int64_t events = 0;           // events returned by next()
    int64_t damaged_regions = 0;  // stretches of bytes skipped to resynchronise
    int64_t skipped_bytes = 0;    // every byte not part of a returned event (damage, oversized events, truncated tail)
    int64_t oversized_events = 0;  // well-formed events longer than max_data_len: skipped unread, not damage
    bool truncated_tail = false;  // the file ends inside an event (a cut log, e.g. the logger killed)
    int64_t truncated_bytes = 0;  // how many of skipped_bytes that cut event holds
};

class LcmLogReader {
public:
    static constexpr uint32_t kSyncWord = 0xEDA1DA01u;
    static constexpr std::size_t kHeaderSize = 28;  // sync + event number + utime + two lengths
    static constexpr std::size_t kDefaultReadAhead = 64 * 1024;

    // Reads the regular file at `path`. max_data_len bounds what one event
    // may claim (pass the largest message the configuration allows); the
    // buffer, about max_channel_len + max_data_len + read_ahead bytes, is
    // allocated here once. Lengths above INT32_MAX are clamped to it (the
    // format's lengths are int32). Longer events are skipped (oversized_events).
    LcmLogReader(const std::string& path, std::size_t max_data_len, std::size_t max_channel_len = 255,
                 std::size_t read_ahead = kDefaultReadAhead);
    // Reads `size` bytes in memory (not copied: they must outlive the reader
    // and its events). Same checks, no buffer.
    LcmLogReader(const uint8_t* bytes, std::size_t size, std::size_t max_data_len,
                 std::size_t max_channel_len = 255);
    ~LcmLogReader();
    LcmLogReader(const LcmLogReader&) = delete;
    LcmLogReader& operator=(const LcmLogReader&) = delete;

    [[nodiscard]] bool good() const { return good_; }  // the file opened (a regular file)
    // The next valid event; false at the end of the file (and on a reader that is not good()).
    [[nodiscard]] bool next(LcmLogEvent& ev);
    [[nodiscard]] const LcmLogStats& stats() const { return stats_; }
    // Any damaged region or a truncated tail so far.
    [[nodiscard]] bool lostData() const { return stats_.damaged_regions > 0 || stats_.truncated_tail; }
    [[nodiscard]] int64_t fileSize() const { return size_; }

private:
    enum class Verdict { kValid, kOversized, kTruncated, kInvalid };
    struct Header {
        int64_t event_number = 0, utime = 0;
        uint32_t channel_len = 0, data_len = 0;
        uint64_t total = 0;  // header + channel + data
    };

    // Pointer to bytes [off, off + len) of the file, or nullptr if the file
    // turned out shorter (size_ is then lowered to what could be read).
    // Precondition: off + len <= size_ and len <= capacity.
    const uint8_t* ensure(int64_t off, std::size_t len);
    // Copies bytes [off, off + len) (a few bytes) without moving the window.
    bool peek(int64_t off, std::size_t len, uint8_t* out);
    // Whether a header whose sync word is damaged but whose lengths hold and
    // whose event ends at a sync word (or the end of the file) starts at off.
    bool headerChains(int64_t off);
    std::size_t readAt(int64_t off, uint8_t* dst, std::size_t len);
    Verdict evaluate(int64_t off, Header& h);
    // First position >= from (and < size_) where a sync word, or the prefix
    // of one that the end of the file cuts, begins; -1 if none.
    int64_t findSync(int64_t from);
    void skip(int64_t from, int64_t to, bool as_damage);

    bool good_ = false;
    int fd_ = -1;
    const uint8_t* mem_ = nullptr;  // in-memory mode
    int64_t size_ = 0;
    int64_t pos_ = 0;
    uint64_t max_data_len_ = 0, max_channel_len_ = 0;
    std::vector<uint8_t> buf_;  // file mode: a window onto the file
    int64_t win_off_ = 0;
    std::size_t win_len_ = 0;
    LcmLogStats stats_;
};

}  // namespace sonarfusion
