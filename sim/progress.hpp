// A one-line progress bar on stderr, redrawn only when the percentage changes.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>

namespace sonarfusion::sim {

class ProgressBar {
public:
    ProgressBar(int64_t total, bool enabled)
        : total_(total > 0 ? total : 1), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

    void update(int64_t done) {
        if (!enabled_) return;
        const int percent = static_cast<int>(100 * done / total_);
        if (percent == last_percent_) return;
        last_percent_ = percent;
        const int filled = percent * kWidth / 100;
        char bar[kWidth + 1];
        for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
        bar[kWidth] = '\0';
        std::fprintf(stderr, "\r[%s] %3d%% %lld/%lld sequences, %.1f s", bar, percent, static_cast<long long>(done),
                     static_cast<long long>(total_), elapsed());
        std::fflush(stderr);
    }
    void finish() {
        if (enabled_) std::fprintf(stderr, "\n");
    }
    [[nodiscard]] double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    static constexpr int kWidth = 40;
    int64_t total_;
    bool enabled_;
    int last_percent_ = -1;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace sonarfusion::sim
