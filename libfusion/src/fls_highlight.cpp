#include "sonarfusion/fls_highlight.hpp"

#include <algorithm>
#include <cmath>

namespace sonarfusion {

FlsHighlight::FlsHighlight(int max_rows, int max_cols, int half_window, double false_alarm)
    : max_rows_(std::max(0, max_rows)), max_cols_(std::max(0, max_cols)), half_(std::max(0, half_window)) {
    const std::size_t px = static_cast<std::size_t>(max_rows_) * static_cast<std::size_t>(max_cols_);
    bright_.assign(px, 0);
    mask_.assign(px, 0);
    integral_.assign(static_cast<std::size_t>(max_rows_ + 1) * static_cast<std::size_t>(max_cols_ + 1), 0);
    scratch_.assign(static_cast<std::size_t>(max_cols_), 0);
    returned_.assign(static_cast<std::size_t>(max_cols_), 0);
    bright_list_.assign(px, 0);
    need_.assign(static_cast<std::size_t>(max_rows_), 0);
    const int window = (2 * half_ + 1) * (2 * half_ + 1);
    need_by_rate_.resize(kRateSteps + 1);
    for (int k = 0; k <= kRateSteps; ++k)
        need_by_rate_[static_cast<std::size_t>(k)] =
            static_cast<int16_t>(minimumBright(window, static_cast<double>(k) / kRateSteps, false_alarm));
}

int FlsHighlight::minimumBright(int n, double p, double false_alarm) {
    if (p <= 0.0) return 1;
    if (p >= 1.0) return n + 1;
    // P(K >= k) for K ~ Binomial(n, p), summed from k = n down.
    double tail = 0.0;
    for (int k = n; k >= 0; --k) {
        tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) + k * std::log(p) +
                         (n - k) * std::log1p(-p));
        if (tail >= false_alarm) return k + 1;
    }
    return 0;
}

void FlsHighlight::compute(const FlsFrame& frame, int vote_threshold, int noise_level, const int* seabed_row) {
    const int rows = frame.rows, cols = frame.cols;
    count_ = 0;
    valid_ = rows <= max_rows_ && cols <= max_cols_ && rows > 0 && cols > 0;
    if (!valid_) return;
    cols_ = cols;
    const auto px = [&](int r, int c) { return static_cast<std::size_t>(r) * cols + c; };
    std::fill(bright_.begin(), bright_.begin() + static_cast<std::ptrdiff_t>(px(rows, 0)), 0);
    std::fill(mask_.begin(), mask_.begin() + static_cast<std::ptrdiff_t>(px(rows, 0)), 0);
    // Only rows 0..deepest hold seabed pixels (none beyond any beam's nearest
    // seabed row), so only they are ranked, hold bright pixels, and need the
    // summed-area table (with the window's half below them).
    int deepest = -1;
    for (int c = 0; c < cols; ++c) deepest = std::max(deepest, std::min(seabed_row[c], rows - 1));
    int n_bright = 0;
    // Seabed row k (k rows beyond each beam's nearest seabed range): its 90th
    // percentile over the pixels that returned (above the noise: a shadow is no
    // seabed speckle, and beside a large one the lit seabed would stand out),
    // and the rate of bright pixels among them.
    for (int k = 0; k <= deepest; ++k) {
        int n = 0;
        uint8_t strongest = 0;
        for (int c = 0; c < cols; ++c) {
            const int r = seabed_row[c] - k;
            if (seabed_row[c] >= 0 && r >= 0 && frame.data[px(r, c)] > noise_level) {
                returned_[n] = static_cast<uint32_t>(px(r, c));
                scratch_[n++] = frame.data[px(r, c)];
                strongest = std::max(strongest, frame.data[px(r, c)]);
            }
        }
        need_[k] = 0;
        if (n == 0 || strongest <= vote_threshold) continue;  // nothing here can be bright
        const auto q = scratch_.begin() + (9 * n) / 10;
        std::nth_element(scratch_.begin(), q, scratch_.begin() + n);
        const int level = std::max<int>(*q, vote_threshold + 1);
        int bright = 0;
        for (int j = 0; j < n; ++j) {  // at or above the level: above the noise too
            const uint32_t i = returned_[j];
            if (frame.data[i] < level) continue;
            bright_[i] = 1;
            bright_list_[n_bright++] = i;
            ++bright;
        }
        const int rate_step = (bright * kRateSteps + n - 1) / n;  // rounded up: fewer false alarms
        need_[k] = need_by_rate_[static_cast<std::size_t>(rate_step)];
    }
    if (n_bright == 0) return;
    const int table_rows = std::min(rows, deepest + half_ + 1);  // the windows' last row
    const std::size_t stride = static_cast<std::size_t>(cols) + 1;
    std::fill(integral_.begin(), integral_.begin() + static_cast<std::ptrdiff_t>(stride), 0);
    for (int r = 0; r < table_rows; ++r) {
        int32_t run = 0;
        integral_[(r + 1) * stride] = 0;
        for (int c = 0; c < cols; ++c) {
            run += bright_[px(r, c)];
            integral_[(r + 1) * stride + c + 1] = integral_[r * stride + c + 1] + run;
        }
    }
    for (int j = 0; j < n_bright; ++j) {
        const uint32_t i = bright_list_[j];
        const int r = static_cast<int>(i / static_cast<uint32_t>(cols)), c = static_cast<int>(i % static_cast<uint32_t>(cols));
        const int r0 = std::max(0, r - half_), r1 = std::min(rows, r + half_ + 1);
        const int c0 = std::max(0, c - half_), c1 = std::min(cols, c + half_ + 1);
        const int32_t n = integral_[r1 * stride + c1] - integral_[r0 * stride + c1] - integral_[r1 * stride + c0] +
                          integral_[r0 * stride + c0];
        // The window spans 2h + 1 seabed rows: it must stand out against the
        // brightest-speckled of them (their rates differ; ties at saturation
        // make a row's rate high).
        int need = 0;
        for (int rr = r0; rr < r1; ++rr)
            if (rr <= seabed_row[c]) need = std::max<int>(need, need_[seabed_row[c] - rr]);
        if (n >= need) {
            mask_[i] = 1;
            ++count_;
        }
    }
}

}  // namespace sonarfusion
