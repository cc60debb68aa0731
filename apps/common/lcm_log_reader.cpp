#include "lcm_log_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>

namespace sonarfusion {

namespace {
constexpr uint8_t kSyncBytes[4] = {0xED, 0xA1, 0xDA, 0x01};
constexpr uint64_t kInt32Max = static_cast<uint64_t>(std::numeric_limits<int32_t>::max());

uint32_t be32(const uint8_t* p) {
    return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
uint64_t be64(const uint8_t* p) { return (uint64_t{be32(p)} << 32) | be32(p + 4); }
// Two's complement reinterpretation without implementation-defined conversions.
int32_t asInt32(uint32_t v) {
    int32_t r;
    std::memcpy(&r, &v, sizeof r);
    return r;
}
int64_t asInt64(uint64_t v) {
    int64_t r;
    std::memcpy(&r, &v, sizeof r);
    return r;
}
}  // namespace

LcmLogReader::LcmLogReader(const std::string& path, std::size_t max_data_len, std::size_t max_channel_len,
                           std::size_t read_ahead)
    : max_data_len_(std::min<uint64_t>(max_data_len, kInt32Max)),
      max_channel_len_(std::min<uint64_t>(max_channel_len, kInt32Max)) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) return;
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size < 0) {
        ::close(fd_);
        fd_ = -1;
        return;
    }
    size_ = static_cast<int64_t>(st.st_size);
    // Room for the largest acceptable event plus the read-ahead, but never
    // more than the file: memory is bounded by max_data_len whatever the file says.
    read_ahead = std::min<std::size_t>(read_ahead, std::size_t{1} << 30);
    const uint64_t capacity = kHeaderSize + max_channel_len_ + max_data_len_ + 4 + read_ahead;
    buf_.resize(static_cast<std::size_t>(std::min<uint64_t>(capacity, static_cast<uint64_t>(size_))));
    good_ = true;
}

LcmLogReader::LcmLogReader(const uint8_t* bytes, std::size_t size, std::size_t max_data_len,
                           std::size_t max_channel_len)
    : mem_(bytes),
      max_data_len_(std::min<uint64_t>(max_data_len, kInt32Max)),
      max_channel_len_(std::min<uint64_t>(max_channel_len, kInt32Max)) {
    good_ = bytes != nullptr || size == 0;
    size_ = good_ ? static_cast<int64_t>(std::min<std::size_t>(size, std::numeric_limits<int64_t>::max())) : 0;
}

LcmLogReader::~LcmLogReader() {
    if (fd_ >= 0) ::close(fd_);
}

std::size_t LcmLogReader::readAt(int64_t off, uint8_t* dst, std::size_t len) {
    std::size_t got = 0;
    while (got < len) {
        const ssize_t n = ::pread(fd_, dst + got, len - got, static_cast<off_t>(off) + static_cast<off_t>(got));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;  // end of file (the file shrank) or a read error: the file ends here
        got += static_cast<std::size_t>(n);
    }
    return got;
}

const uint8_t* LcmLogReader::ensure(int64_t off, std::size_t len) {
    if (off < 0 || off > size_ || len > static_cast<uint64_t>(size_ - off)) return nullptr;
    if (mem_ || size_ == 0) return mem_ ? mem_ + off : nullptr;
    const int64_t win_end = win_off_ + static_cast<int64_t>(win_len_);
    if (off >= win_off_ && off + static_cast<int64_t>(len) <= win_end) return buf_.data() + (off - win_off_);
    if (len > buf_.size()) return nullptr;  // cannot happen: callers ask for at most one event
    std::size_t keep = 0;
    if (off >= win_off_ && off < win_end) {
        keep = static_cast<std::size_t>(win_end - off);
        std::memmove(buf_.data(), buf_.data() + (off - win_off_), keep);
    }
    win_off_ = off;
    win_len_ = keep;
    const std::size_t want = static_cast<std::size_t>(std::min<uint64_t>(buf_.size(), static_cast<uint64_t>(size_ - off)));
    if (win_len_ < want) {
        win_len_ += readAt(off + static_cast<int64_t>(win_len_), buf_.data() + win_len_, want - win_len_);
        if (win_len_ < want) size_ = off + static_cast<int64_t>(win_len_);  // shorter than fstat said
    }
    return win_len_ >= len ? buf_.data() : nullptr;
}

bool LcmLogReader::peek(int64_t off, std::size_t len, uint8_t* out) {
    // Small reads (a sync word, two lengths) that leave the window where it is.
    if (off < 0 || off > size_ || len > static_cast<uint64_t>(size_ - off)) return false;
    if (mem_) {
        std::memcpy(out, mem_ + off, len);
        return true;
    }
    const int64_t win_end = win_off_ + static_cast<int64_t>(win_len_);
    if (off >= win_off_ && off + static_cast<int64_t>(len) <= win_end) {
        std::memcpy(out, buf_.data() + (off - win_off_), len);
        return true;
    }
    const std::size_t got = readAt(off, out, len);
    if (got < len) size_ = off + static_cast<int64_t>(got);
    return got == len;
}

LcmLogReader::Verdict LcmLogReader::evaluate(int64_t off, Header& h) {
    const uint64_t rem = static_cast<uint64_t>(size_ - off);
    const std::size_t n = static_cast<std::size_t>(std::min<uint64_t>(rem, kHeaderSize));
    if (n == 0) return Verdict::kInvalid;
    const uint8_t* p = ensure(off, n);
    if (!p) return Verdict::kInvalid;
    if (std::memcmp(p, kSyncBytes, std::min<std::size_t>(n, 4)) != 0) return Verdict::kInvalid;
    // Fields that the end of the file cuts cannot be checked; those it leaves whole must hold.
    if (n >= 24) {
        const int32_t cl = asInt32(be32(p + 20));
        if (cl < 1 || static_cast<uint64_t>(cl) > max_channel_len_) return Verdict::kInvalid;
        h.channel_len = static_cast<uint32_t>(cl);
    }
    if (n < kHeaderSize) return Verdict::kTruncated;
    const int32_t dl = asInt32(be32(p + 24));
    if (dl < 0) return Verdict::kInvalid;
    h.data_len = static_cast<uint32_t>(dl);
    h.event_number = asInt64(be64(p + 4));
    h.utime = asInt64(be64(p + 12));
    h.total = kHeaderSize + uint64_t{h.channel_len} + uint64_t{h.data_len};  // < 2^33: no overflow
    const bool oversized = h.data_len > max_data_len_;
    // Longer than we accept and longer than the file: damage, not a cut.
    if (h.total > rem) return oversized ? Verdict::kInvalid : Verdict::kTruncated;
    // The next sync word (or as much of it as the file holds), or the exact end of the file.
    const std::size_t follow = static_cast<std::size_t>(std::min<uint64_t>(rem - h.total, 4));
    if (follow > 0) {
        uint8_t f[4];
        if (!peek(off + static_cast<int64_t>(h.total), follow, f)) return Verdict::kInvalid;
        if (std::memcmp(f, kSyncBytes, follow) != 0 && !headerChains(off + static_cast<int64_t>(h.total)))
            return Verdict::kInvalid;
    }
    // A well-formed event (it ends at a sync word) too long for us: skipped
    // unread, so memory stays bounded by max_data_len.
    return oversized ? Verdict::kOversized : Verdict::kValid;
}

bool LcmLogReader::headerChains(int64_t off) {
    // The header at `off` has a damaged sync word; its lengths must be in
    // range and its event must end at the next sync word or the end of the
    // file. Then the event before it ended where it said (a length corrupted
    // to another in-range value almost never lands on such a header).
    if (size_ - off < static_cast<int64_t>(kHeaderSize)) return false;
    uint8_t len[8];
    if (!peek(off + 20, sizeof len, len)) return false;
    const int32_t cl = asInt32(be32(len)), dl = asInt32(be32(len + 4));
    if (cl < 1 || static_cast<uint64_t>(cl) > max_channel_len_ || dl < 0) return false;
    const uint64_t total = kHeaderSize + static_cast<uint64_t>(cl) + static_cast<uint64_t>(dl);
    const uint64_t rem = static_cast<uint64_t>(size_ - off);
    if (total > rem) return false;
    const std::size_t follow = static_cast<std::size_t>(std::min<uint64_t>(rem - total, 4));
    uint8_t f[4];
    if (follow > 0 && !peek(off + static_cast<int64_t>(total), follow, f)) return false;
    return follow == 0 || std::memcmp(f, kSyncBytes, follow) == 0;
}

int64_t LcmLogReader::findSync(int64_t from) {
    int64_t q = from;
    while (q < size_) {
        const uint64_t rem = static_cast<uint64_t>(size_ - q);
        std::size_t n = static_cast<std::size_t>(mem_ ? rem : std::min<uint64_t>(rem, buf_.size()));
        if (!mem_) {
            // Scan what the window already holds before moving it: moving it for
            // every candidate would cost a buffer's worth of copying each time.
            const int64_t win_end = win_off_ + static_cast<int64_t>(win_len_);
            if (q >= win_off_ && q < win_end && (win_end - q >= 4 || win_end == size_))
                n = static_cast<std::size_t>(win_end - q);
        }
        const uint8_t* p = ensure(q, n);
        if (!p) return -1;  // the file shrank under us; the caller sees size_ change
        std::size_t i = 0;
        bool straddles = false;
        while (i < n) {
            const void* hit = std::memchr(p + i, kSyncBytes[0], n - i);
            if (!hit) break;
            const std::size_t j = static_cast<std::size_t>(static_cast<const uint8_t*>(hit) - p);
            const std::size_t m = static_cast<std::size_t>(std::min<uint64_t>(4, rem - j));
            if (j + m > n) {  // the candidate runs past this chunk: look again from it
                straddles = true;
                i = j;
                break;
            }
            if (std::memcmp(p + j, kSyncBytes, m) == 0) return q + static_cast<int64_t>(j);
            i = j + 1;
        }
        q += static_cast<int64_t>(straddles && i > 0 ? i : n);
    }
    return -1;
}

void LcmLogReader::skip(int64_t from, int64_t to, bool as_damage) {
    if (to <= from) return;
    stats_.skipped_bytes += to - from;
    if (as_damage) {
        ++stats_.damaged_regions;
    } else {
        stats_.truncated_tail = true;
        stats_.truncated_bytes += to - from;
    }
}

bool LcmLogReader::next(LcmLogEvent& ev) {
    if (!good_) return false;
    for (;;) {
        if (pos_ >= size_) return false;
        // size_ only ever shrinks (a file cut while we read it); when it does,
        // the step is redone against the new size before any count changes.
        const int64_t size_before = size_;
        Header h;
        const Verdict v = evaluate(pos_, h);
        if (size_ != size_before) continue;
        if (v == Verdict::kOversized) {
            ++stats_.oversized_events;
            stats_.skipped_bytes += static_cast<int64_t>(h.total);
            pos_ += static_cast<int64_t>(h.total);
            continue;
        }
        if (v == Verdict::kValid) {
            const uint8_t* p = ensure(pos_, static_cast<std::size_t>(h.total));
            if (!p) {
                if (size_ != size_before) continue;
                skip(pos_, size_, true);  // cannot happen (the buffer holds any valid event); never loop on it
                pos_ = size_;
                return false;
            }
            ev.event_number = h.event_number;
            ev.utime = h.utime;
            ev.channel = std::string_view(reinterpret_cast<const char*>(p + kHeaderSize), h.channel_len);
            ev.data = p + kHeaderSize + h.channel_len;
            ev.size = h.data_len;
            ev.file_offset = pos_;
            pos_ += static_cast<int64_t>(h.total);
            ++stats_.events;
            return true;
        }
        // Damage, or the file ends inside this event: the next event that
        // passes every check ends the damaged region.
        int64_t truncated_at = v == Verdict::kTruncated ? pos_ : -1;
        int64_t valid_at = -1;
        for (int64_t q = findSync(pos_ + 1); q >= 0 && size_ == size_before; q = findSync(q + 1)) {
            Header hq;
            const Verdict vq = evaluate(q, hq);
            if (size_ != size_before) break;
            if (vq == Verdict::kValid || vq == Verdict::kOversized) {
                valid_at = q;
                break;
            }
            if (vq == Verdict::kTruncated && truncated_at < 0) truncated_at = q;
        }
        if (size_ != size_before) continue;
        if (valid_at >= 0) {
            skip(pos_, valid_at, true);
            pos_ = valid_at;
            continue;
        }
        if (truncated_at < 0) {
            skip(pos_, size_, true);
        } else {
            skip(pos_, truncated_at, true);
            skip(truncated_at, size_, false);
        }
        pos_ = size_;
        return false;
    }
}

}  // namespace sonarfusion
