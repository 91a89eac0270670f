// The image metrics and ꟻLIP on cases with known answers and on the papers' properties.
#include <gtest/gtest.h>

#include <cmath>

#include "svetlo/core/flip.h"
#include "svetlo/core/image_metrics.h"

namespace svetlo {
namespace {

TEST(PixelMetrics, ConstantImages) {
    Image a(8, 4, Color(0.5f)), b(8, 4, Color(0.25f));
    PixelMetrics m = pixel_metrics(a, b);
    EXPECT_NEAR(m.mae, 0.25, 1e-12);
    EXPECT_NEAR(m.rmse, 0.25, 1e-12);
    EXPECT_NEAR(m.relmse, 0.0625 / (0.26 * 0.26), 1e-9);  // b + 0.01 in the denominator
    // relMSE divides by the second image, the reference: not symmetric.
    EXPECT_NEAR(pixel_metrics(b, a).relmse, 0.0625 / (0.51 * 0.51), 1e-9);
}

TEST(PixelMetrics, OneDifferentChannel) {
    Image a(10, 10, Color(0.2f)), b = a;
    b.at(3, 7).g = 0.7f;  // one channel of one pixel, off by 0.5
    PixelMetrics m = pixel_metrics(a, b);
    const double d = 0.7 - static_cast<double>(0.2f), n = 300.0;
    EXPECT_NEAR(m.mae, std::abs(static_cast<float>(0.2f - 0.7f)) / n, 1e-9);
    EXPECT_NEAR(m.rmse, std::sqrt(d * d / n), 1e-7);
    EXPECT_NEAR(m.relmse, d * d / ((0.7 + 0.01) * (0.7 + 0.01)) / n, 1e-7);
    EXPECT_EQ(pixel_metrics(a, a).rmse, 0.0);
    std::vector<float> per_pixel = pixel_errors(a, b, "mae");
    EXPECT_NEAR(per_pixel[7 * 10 + 3], 0.5 / 3.0, 1e-6);
    EXPECT_EQ(per_pixel[0], 0.0f);
}

TEST(PixelMetrics, NonFiniteCountsAsZero) {
    Image a(1, 1, Color(std::nanf(""))), b(1, 1, Color(0.0f));
    EXPECT_EQ(pixel_metrics(a, b).mae, 0.0);
}

TEST(Flip, IdenticalImagesGiveZero) {
    Image a(24, 16);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 24; ++i) a.at(i, j) = Color(i / 24.0f, j / 16.0f, 0.3f);
    EXPECT_EQ(flip_ldr(a, a).mean, 0.0);
    Image hdr = a;
    for (Color& c : hdr.pixels) c *= 40.0f;
    EXPECT_EQ(flip_hdr(hdr, hdr).mean, 0.0);
}

TEST(Flip, BlackAgainstWhiteIsTheRedistributedHyab) {
    // Constant images have no features, so the error is the colour term alone: HyAB between
    // L* = 0 and 100 is 100; 100^0.7 = 25.12 lies above 0.4 c_max (c_max = 41.276, green
    // against blue, Hunt-adjusted), so it maps to 0.95 + (25.12 - 16.51) / (41.28 - 16.51)
    // 0.05 = 0.96738.
    Image black(16, 16, Color(0.0f)), white(16, 16, Color(1.0f));
    FlipMap m = flip_ldr(black, white);
    EXPECT_NEAR(m.mean, 0.96738, 1e-4);
    for (float e : m.error) EXPECT_NEAR(e, 0.96738f, 1e-4f);
}

TEST(Flip, LdrIsSymmetric) {
    Image a(20, 20, Color(0.3f)), b(20, 20, Color(0.3f));
    for (int j = 5; j < 12; ++j)
        for (int i = 3; i < 9; ++i) b.at(i, j) = Color(0.9f, 0.2f, 0.1f);
    a.at(15, 15) = Color(0.0f, 0.0f, 1.0f);
    FlipMap ab = flip_ldr(a, b), ba = flip_ldr(b, a);
    EXPECT_GT(ab.mean, 0.01);
    for (size_t k = 0; k < ab.error.size(); ++k) EXPECT_NEAR(ab.error[k], ba.error[k], 1e-6f);
}

TEST(Flip, OnePixelChangeFallsWithPixelsPerDegree) {
    // Seen from farther away (more pixels per degree), one changed pixel is harder to see.
    Image a(48, 48, Color(0.5f)), b = a;
    b.at(24, 24) = Color(0.0f);
    double previous = 1.0;
    for (float ppd : {10.0f, 30.0f, 67.0f, 120.0f}) {
        FlipMap m = flip_ldr(a, b, ppd);
        float peak = m.error[24 * 48 + 24];
        EXPECT_LT(peak, previous) << ppd;
        EXPECT_GT(peak, 0.0f);
        previous = peak;
    }
}

TEST(Flip, OneAndTwoThreadsAgree) {
    Image a(33, 17, Color(0.1f)), b = a;
    for (int i = 0; i < 33; ++i) b.at(i, 8) = Color(0.8f);
    FlipMap one = flip_ldr(a, b, kFlipPixelsPerDegree, 1),
            two = flip_ldr(a, b, kFlipPixelsPerDegree, 2);
    EXPECT_EQ(one.error, two.error);
}

TEST(Flip, HdrExposuresSpanMaximumToMedian) {
    // The start exposure maps the brightest luminance, the stop the median, to where the
    // ACES curve reaches 0.85; at least two exposures, one stop or less apart.
    Image hdr(10, 10, Color(1.0f));
    hdr.at(0, 0) = Color(64.0f);
    std::vector<float> e = flip_hdr_exposures(hdr);
    ASSERT_GE(e.size(), 2u);
    EXPECT_NEAR(e.back() - e.front(), 6.0f, 1e-4f);  // log2(64 / 1)
    EXPECT_EQ(e.size(), 6u);
    // An all-black reference: exposure 0, twice.
    std::vector<float> zero = flip_hdr_exposures(Image(4, 4));
    EXPECT_EQ(zero, (std::vector<float>{0.0f, 0.0f}));
}

TEST(Flip, HdrSeesErrorsInTheHighlights) {
    // Two images that differ only far above 1: clipped, LDR-ꟻLIP cannot see it; HDR-ꟻLIP's
    // short exposures do.
    Image a(16, 16, Color(0.2f)), b = a;
    for (int j = 4; j < 12; ++j)
        for (int i = 4; i < 12; ++i) a.at(i, j) = Color(50.0f), b.at(i, j) = Color(100.0f);
    EXPECT_EQ(flip_ldr(a, b).mean, 0.0);
    EXPECT_GT(flip_hdr(a, b).mean, 0.01);
}

TEST(Magma, Ends) {
    EXPECT_NEAR(magma(0.0f).b, 4.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(magma(1.0f).r, 252.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(magma(2.0f).r, 252.0f / 255.0f, 1e-6f);  // clipped
}

}  // namespace
}  // namespace svetlo
