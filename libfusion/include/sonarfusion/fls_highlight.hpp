// FLS highlights: image regions brighter than the seabed returns at the same
// place on the seabed (docs/algorithm.md, "Highlights the seabed cannot explain").
//
// Where a beam meets the seabed, its pixels are the seabed's speckle, and how
// bright that speckle is depends on the grazing angle: on how far beyond the
// beam's nearest seabed range the pixel lies. So pixels are compared across
// beams at the same number of rows beyond that range ("seabed rows"): a pixel is
// bright when it reaches the 90th percentile of its seabed row's returns (pixels
// above the image's noise; and the vote threshold), which speckle does at the
// seabed row's own rate p. An object on
// the seabed returns a compact bright region (a surface facing the sonar, of
// higher impedance). A pixel is a highlight when it is bright and its window of
// (2h+1)^2 pixels holds so many bright pixels that speckle at rate p gives that
// many with probability below the false-alarm rate (binomial tail).
// Buffers are sized at construction; compute() allocates nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "sonarfusion/fls_model.hpp"

namespace sonarfusion {

class FlsHighlight {
public:
    FlsHighlight(int max_rows, int max_cols, int half_window, double false_alarm);
    // Marks the highlights of `frame` (rows x cols within the capacity; a larger
    // frame marks nothing). seabed_row[c]: the row of column c where the seabed
    // could first return (rows count from the far end, so the seabed's pixels
    // are rows 0..seabed_row[c]); negative: the beam never meets the seabed and
    // none of its pixels is judged. Pixels at or below `noise_level` (the image's
    // noise, noiseLevel) are not seabed returns and set no statistic; pixels at
    // or below `vote_threshold` are never marked.
    void compute(const FlsFrame& frame, int vote_threshold, int noise_level, const int* seabed_row);
    // Pixel (row, col) of the last computed frame is a highlight.
    [[nodiscard]] bool at(int row, int col) const {
        return valid_ && mask_[static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) +
                               static_cast<std::size_t>(col)] != 0;
    }
    [[nodiscard]] int highlights() const { return count_; }
    // Fewest bright pixels of n in a window that speckle at rate p reaches with
    // probability below `false_alarm` (n + 1: none).
    [[nodiscard]] static int minimumBright(int n, double p, double false_alarm);

private:
    static constexpr int kRateSteps = 256;  // rates tabulated in steps of 1/256, rounded up
    int max_rows_, max_cols_, half_;
    int cols_ = 0, count_ = 0;
    bool valid_ = false;
    std::vector<uint8_t> bright_, mask_;
    std::vector<int32_t> integral_;    // (rows + 1) x (cols + 1) summed-area table of bright_
    std::vector<uint8_t> scratch_;     // one seabed row's pixels
    std::vector<uint32_t> returned_;   // where they lie (pixel index)
    std::vector<uint32_t> bright_list_;  // the frame's bright pixels, seabed row by seabed row
    std::vector<int16_t> need_;        // per seabed row: bright pixels a window needs
    std::vector<int16_t> need_by_rate_;  // minimumBright at rate k / kRateSteps
};

}  // namespace sonarfusion
