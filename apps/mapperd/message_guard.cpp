#include "message_guard.hpp"

#include <sonarfusion/fls_image_t.hpp>
#include <sonarfusion/nav_state_t.hpp>
#include <sonarfusion/ps_ping_t.hpp>

namespace sonarfusion::guard {

const char* verdictName(Verdict v) {
    switch (v) {
        case Verdict::Ok: return "ok";
        case Verdict::Truncated: return "truncated";
        case Verdict::BadFingerprint: return "bad_fingerprint";
        case Verdict::BadCount: return "bad_count";
        case Verdict::Trailing: return "trailing_bytes";
    }
    return "unknown";
}

namespace {
// A bounds-checked cursor over an LCM encoding.
class Cursor {
public:
    Cursor(const void* d, std::size_t n) : p_(static_cast<const uint8_t*>(d)), n_(n) {}
    bool skip(std::size_t k) {
        if (k > n_ - off_) return false;
        off_ += k;
        return true;
    }
    bool int32(int32_t& v) {
        if (4 > n_ - off_) return false;
        v = static_cast<int32_t>((uint32_t{p_[off_]} << 24) | (uint32_t{p_[off_ + 1]} << 16) |
                                 (uint32_t{p_[off_ + 2]} << 8) | uint32_t{p_[off_ + 3]});
        off_ += 4;
        return true;
    }
    bool int64(int64_t& v) {
        if (8 > n_ - off_) return false;
        uint64_t u = 0;
        for (int i = 0; i < 8; ++i) u = (u << 8) | p_[off_ + i];
        v = static_cast<int64_t>(u);
        off_ += 8;
        return true;
    }
    // LCM string: int32 length including the NUL, then the bytes.
    Verdict string(int32_t max_len) {
        int32_t len = 0;
        if (!int32(len)) return Verdict::Truncated;
        if (len < 1 || len > max_len) return Verdict::BadCount;
        return skip(static_cast<std::size_t>(len)) ? Verdict::Ok : Verdict::Truncated;
    }
    // An array count that must be >= 0 and whose elements fit in what is left.
    Verdict array(int32_t& count, std::size_t elem, int32_t max_count) {
        if (!int32(count)) return Verdict::Truncated;
        if (count < 0 || count > max_count) return Verdict::BadCount;
        if (static_cast<std::size_t>(count) * elem > n_ - off_) return Verdict::Truncated;
        off_ += static_cast<std::size_t>(count) * elem;
        return Verdict::Ok;
    }
    [[nodiscard]] bool atEnd() const { return off_ == n_; }

private:
    const uint8_t* p_;
    std::size_t n_;
    std::size_t off_ = 0;
};

Verdict fingerprint(Cursor& c, int64_t expected) {
    int64_t fp = 0;
    if (!c.int64(fp)) return Verdict::Truncated;
    return fp == expected ? Verdict::Ok : Verdict::BadFingerprint;
}

#define SF_TRY(expr)                            \
    do {                                        \
        if (!(expr)) return Verdict::Truncated; \
    } while (0)
#define SF_CHECK(expr)                 \
    do {                               \
        const Verdict v_ = (expr);     \
        if (v_ != Verdict::Ok) return v_; \
    } while (0)

}  // namespace

Limits limitsFor(const MapperConfig& cfg) {
    Limits l;
    l.fls_beams = cfg.fls.beams;
    l.fls_rows = cfg.fls.rows;
    l.fls_pixels = cfg.fls.beams * cfg.fls.rows;
    l.ps_bins = cfg.ps.bins;
    return l;
}

Verdict checkNav(const void* data, std::size_t size) {
    Cursor c(data, size);
    SF_CHECK(fingerprint(c, nav_state_t::getHash()));
    SF_TRY(c.skip(8 + 8 + 3 * 8 + 3 * 8 + 3 * 8 + 8));
    return c.atEnd() ? Verdict::Ok : Verdict::Trailing;
}

Verdict checkFls(const void* data, std::size_t size, const Limits& limits) {
    Cursor c(data, size);
    SF_CHECK(fingerprint(c, fls_image_t::getHash()));
    SF_TRY(c.skip(8 + 8));  // utime, seq
    SF_CHECK(c.string(limits.name_bytes));  // sensor_name
    SF_TRY(c.skip(4 + 4 + 3 * 4 + 2 * 4 + 4 + 4 + 4));
    int32_t beams = 0, ranges = 0, pixels = 0;
    SF_CHECK(c.array(beams, 4, limits.fls_beams));
    SF_CHECK(c.array(ranges, 4, limits.fls_rows));
    SF_CHECK(c.array(pixels, 1, limits.fls_pixels));
    return c.atEnd() ? Verdict::Ok : Verdict::Trailing;
}

Verdict checkPs(const void* data, std::size_t size, const Limits& limits) {
    Cursor c(data, size);
    SF_CHECK(fingerprint(c, ps_ping_t::getHash()));
    SF_TRY(c.skip(8 + 8));
    SF_CHECK(c.string(limits.name_bytes));
    SF_TRY(c.skip(3 * 4 + 2 * 4 + 4 + 4 + 4 + 4 + 4 + 4));
    int32_t bins = 0;
    SF_CHECK(c.array(bins, 1, limits.ps_bins));
    return c.atEnd() ? Verdict::Ok : Verdict::Trailing;
}

}  // namespace sonarfusion::guard
