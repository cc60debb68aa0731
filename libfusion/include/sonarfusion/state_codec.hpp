// Byte-level writer and reader for checkpoints of the pipeline state: plain
// little-endian copies of trivially copyable values into a buffer the caller
// sized once (the writer never grows it), and a bounds-checked reader that
// fails instead of reading past the end. No file I/O here: the daemon owns it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace sonarfusion {

class StateWriter {
public:
    // Writes into buf[0, capacity); overflow() reports a buffer too small.
    StateWriter(uint8_t* buf, std::size_t capacity) : p_(buf), cap_(capacity) {}
    void bytes(const void* src, std::size_t n) {
        if (overflow_ || n > cap_ - off_) {
            overflow_ = true;
            return;
        }
        std::memcpy(p_ + off_, src, n);
        off_ += n;
    }
    template <class T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes(&v, sizeof(T));
    }
    // Room for n bytes the caller fills in place (e.g. an LCM encode); null,
    // and overflow() set, when they do not fit.
    [[nodiscard]] uint8_t* reserve(std::size_t n) {
        if (overflow_ || n > cap_ - off_) {
            overflow_ = true;
            return nullptr;
        }
        uint8_t* at = p_ + off_;
        off_ += n;
        return at;
    }
    [[nodiscard]] std::size_t size() const { return off_; }
    [[nodiscard]] bool overflow() const { return overflow_; }

private:
    uint8_t* p_;
    std::size_t cap_, off_ = 0;
    bool overflow_ = false;
};

class StateReader {
public:
    StateReader(const uint8_t* buf, std::size_t n) : p_(buf), n_(n) {}
    [[nodiscard]] bool bytes(void* dst, std::size_t n) {
        if (!ok_ || n > n_ - off_) return ok_ = false;
        std::memcpy(dst, p_ + off_, n);
        off_ += n;
        return true;
    }
    template <class T>
    [[nodiscard]] bool pod(T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        return bytes(&v, sizeof(T));
    }
    // The next n bytes in place, or null when fewer are left.
    [[nodiscard]] const uint8_t* view(std::size_t n) {
        if (!ok_ || n > n_ - off_) {
            ok_ = false;
            return nullptr;
        }
        const uint8_t* at = p_ + off_;
        off_ += n;
        return at;
    }
    // A count written by the writer that must equal what this build allocated.
    [[nodiscard]] bool expect(uint64_t value) {
        uint64_t v = 0;
        return pod(v) && (v == value || (ok_ = false));
    }
    [[nodiscard]] bool ok() const { return ok_; }
    [[nodiscard]] bool atEnd() const { return off_ == n_; }

private:
    const uint8_t* p_;
    std::size_t n_, off_ = 0;
    bool ok_ = true;
};

}  // namespace sonarfusion
