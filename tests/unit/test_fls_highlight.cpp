// FLS highlights (fls_highlight.hpp): a compact region brighter than the
// seabed's speckle at the same place on the seabed, and nothing on speckle alone
// or on lit seabed beside a shadow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "sonarfusion/fls_highlight.hpp"

using namespace sonarfusion;

namespace {
constexpr int kRows = 200, kCols = 96;

struct Image {
    std::vector<uint8_t> px = std::vector<uint8_t>(static_cast<std::size_t>(kRows) * kCols, 8);
    std::vector<int> seabed_row = std::vector<int>(kCols, 120);  // rows 0..120 lie on the seabed
    FlsFrame frame() const {
        FlsFrame f;
        f.rows = kRows;
        f.cols = kCols;
        f.data = px.data();
        f.data_size = px.size();
        return f;
    }
    uint8_t& at(int r, int c) { return px[static_cast<std::size_t>(r) * kCols + c]; }
    // Seabed speckle on rows 0..120: one pixel in ten bright (200-255), the
    // rest 40-159, from a fixed linear congruential sequence.
    void speckle() {
        uint32_t s = 12345;
        for (int r = 0; r <= 120; ++r)
            for (int c = 0; c < kCols; ++c) {
                s = s * 1664525u + 1013904223u;
                const uint32_t u = s >> 8;
                at(r, c) = static_cast<uint8_t>(u % 10 == 0 ? 200 + (u / 10) % 56 : 40 + (u / 10) % 120);
            }
    }
};
}  // namespace

TEST(FlsHighlight, MinimumBrightIsTheBinomialTailQuantile) {
    auto tail = [](int n, double p, int k) {  // P(K >= k), K ~ Binomial(n, p)
        double t = 0.0;
        for (int j = k; j <= n; ++j) t += std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) +
                                                   j * std::log(p) + (n - j) * std::log1p(-p));
        return t;
    };
    for (double p : {0.1, 0.25, 0.5}) {
        const int k = FlsHighlight::minimumBright(25, p, 1e-6);
        ASSERT_GT(k, 0);
        ASSERT_LE(k, 25);
        EXPECT_LT(tail(25, p, k), 1e-6) << "p " << p;
        EXPECT_GE(tail(25, p, k - 1), 1e-6) << "p " << p;
    }
    EXPECT_EQ(FlsHighlight::minimumBright(25, 1.0, 1e-6), 26) << "every pixel bright: nothing stands out";
    EXPECT_EQ(FlsHighlight::minimumBright(25, 0.0, 1e-6), 1);
}

TEST(FlsHighlight, SpeckleAloneIsNoHighlightAndABrightPatchIs) {
    Image img;
    img.speckle();
    FlsHighlight h(kRows, kCols, 2, 1e-6);
    h.compute(img.frame(), 150, 20, img.seabed_row.data());
    EXPECT_EQ(h.highlights(), 0);
    // A 6 x 6 patch of saturated returns on the seabed (an object's face).
    for (int r = 60; r < 66; ++r)
        for (int c = 40; c < 46; ++c) img.at(r, c) = 255;
    h.compute(img.frame(), 150, 20, img.seabed_row.data());
    int inside = 0;
    for (int r = 60; r < 66; ++r)
        for (int c = 40; c < 46; ++c) inside += h.at(r, c);
    EXPECT_GE(inside, 30) << "of 36";
    EXPECT_LE(h.highlights(), inside + 6) << "only bright speckle touching the patch may join it";
}

TEST(FlsHighlight, LitSeabedBesideAShadowIsNoHighlight) {
    // A large object's shadow darkens all but the 14 port beams on rows 40..100:
    // ranked among all the beams, the lit seabed beside it would be the row's
    // brightest; ranked among the pixels that returned, it is speckle.
    // The lit seabed there is bright speckle (steep incidence): half its pixels
    // at 200-255, half at 100-199.
    Image img;
    img.speckle();
    uint32_t s = 777;
    for (int r = 40; r <= 100; ++r)
        for (int c = 0; c < kCols; ++c) {
            s = s * 1664525u + 1013904223u;
            const uint32_t u = s >> 8;
            img.at(r, c) = c >= 14 ? 8 : static_cast<uint8_t>(u % 2 ? 200 + (u / 2) % 56 : 100 + (u / 2) % 100);
        }
    FlsHighlight h(kRows, kCols, 2, 1e-6);
    h.compute(img.frame(), 150, 20, img.seabed_row.data());
    EXPECT_EQ(h.highlights(), 0);
    h.compute(img.frame(), 150, 0, img.seabed_row.data());  // the shadow counted as seabed
    EXPECT_GT(h.highlights(), 0) << "the test does not show what the noise level does";
}

TEST(FlsHighlight, OnlyPixelsOnTheSeabedAndWithinCapacityAreJudged) {
    Image img;
    for (int r = 150; r < 160; ++r)  // nearer than the seabed: range alone judges these
        for (int c = 10; c < 20; ++c) img.at(r, c) = 255;
    FlsHighlight h(kRows, kCols, 2, 1e-6);
    h.compute(img.frame(), 150, 20, img.seabed_row.data());
    EXPECT_EQ(h.highlights(), 0);
    FlsHighlight small(kRows - 1, kCols, 2, 1e-6);
    img.speckle();
    for (int r = 60; r < 66; ++r)
        for (int c = 40; c < 46; ++c) img.at(r, c) = 255;
    small.compute(img.frame(), 150, 20, img.seabed_row.data());
    EXPECT_EQ(small.highlights(), 0);
    EXPECT_FALSE(small.at(62, 42));
}

TEST(FlsHighlight, AWindowStandsOutAgainstTheBrightestSeabedRowItSpans) {
    // Four seabed rows whose returns all tie at one level (every pixel "bright",
    // rate 1) next to speckle at rate 0.1: judged at its own row's rate, a
    // speckle pixel whose 7 x 7 window reaches three of those rows would count
    // them as 21 of its own kind and stand out.
    Image img;
    img.speckle();
    for (int r = 50; r <= 53; ++r)
        for (int c = 0; c < kCols; ++c) img.at(r, c) = 180;
    FlsHighlight h(kRows, kCols, 3, 1e-6);
    h.compute(img.frame(), 150, 20, img.seabed_row.data());
    EXPECT_EQ(h.highlights(), 0);
}
