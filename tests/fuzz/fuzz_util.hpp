// Shared by the file fuzzers: the input as a real file, without touching the
// disk: a memfd, opened by path through /proc/self/fd (the readers under test
// take paths).
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace sffuzz {

inline std::string asFile(const uint8_t* data, std::size_t size) {
    static const int fd = [] {
        const int f = memfd_create("sf-fuzz-input", MFD_CLOEXEC);
        if (f < 0) std::abort();
        return f;
    }();
    if (ftruncate(fd, 0) != 0) std::abort();
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (n <= 0) std::abort();
        done += static_cast<std::size_t>(n);
    }
    return "/proc/self/fd/" + std::to_string(fd);
}

}  // namespace sffuzz
