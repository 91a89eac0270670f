#include "svetlo/core/sampling.h"

#include <gtest/gtest.h>

#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

TEST(Rng, StreamsAreReproducibleAndDistinct) {
    Rng a = pixel_rng(7, 100), b = pixel_rng(7, 100), c = pixel_rng(7, 101);
    for (int k = 0; k < 100; ++k) {
        uint32_t x = a.next_u32();
        EXPECT_EQ(x, b.next_u32());
        EXPECT_NE(x, c.next_u32());
    }
}

TEST(Rng, UniformMeanAndRange) {
    Rng rng(1, 2);
    double sum = 0.0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        float u = rng.next_float();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        sum += u;
    }
    EXPECT_NEAR(sum / n, 0.5, 3.0 * std::sqrt(1.0 / 12.0 / n) * 2.0);
}

TEST(Sampling, CosineHemisphereHasMeanCosTwoThirds) {
    // E[cos] under pdf cos/pi is 2/3; E[cos^2] = 1/2.
    Rng rng(3, 4);
    double sum = 0.0, sum2 = 0.0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        vec3 d = sample_cosine_hemisphere(rng.next_2d());
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
        sum += d.z;
        sum2 += d.z * d.z;
    }
    EXPECT_NEAR(sum / n, 2.0 / 3.0, 0.003);
    EXPECT_NEAR(sum2 / n, 0.5, 0.003);
}

TEST(Sampling, QuarterCosineAndSineMatchTheLibrarysToARoundingError) {
    for (int k = -1000; k <= 1000; ++k) {
        float x = (kPi / 4.0f) * static_cast<float>(k) / 1000.0f;
        vec2 cs = cos_sin_quarter(x);
        EXPECT_NEAR(cs.x, std::cos(x), 2e-7f) << x;
        EXPECT_NEAR(cs.y, std::sin(x), 2e-7f) << x;
    }
}

TEST(Sampling, ConcentricDiskMapsEveryOctantAsShirleyAndChiu) {
    // The map by its definition, in double: r = the coordinate of larger magnitude, the angle
    // (pi/4) t from the x axis or pi/2 - (pi/4) t, on both sides of every diagonal.
    for (int i = 0; i <= 64; ++i) {
        for (int j = 0; j <= 64; ++j) {
            vec2 u(static_cast<float>(i) / 64.0f, static_cast<float>(j) / 64.0f);
            double a = 2.0 * u.x - 1.0, b = 2.0 * u.y - 1.0, r = 0.0, theta = 0.0;
            if (std::abs(a) > std::abs(b)) {
                r = a;
                theta = (kPi / 4.0) * (b / a);
            } else if (b != 0.0) {
                r = b;
                theta = kPi / 2.0 - (kPi / 4.0) * (a / b);
            }
            vec2 d = sample_disk_concentric(u);
            EXPECT_NEAR(d.x, r * std::cos(theta), 3e-7) << u.x << " " << u.y;
            EXPECT_NEAR(d.y, r * std::sin(theta), 3e-7) << u.x << " " << u.y;
        }
    }
}

TEST(Sampling, TriangleSamplesAreUniform) {
    Rng rng(5, 6);
    double b0 = 0.0, b1 = 0.0;
    const int n = 100000;
    for (int k = 0; k < n; ++k) {
        vec2 b = sample_triangle(rng.next_2d());
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
        b0 += b.x;
        b1 += b.y;
    }
    EXPECT_NEAR(b0 / n, 1.0 / 3.0, 0.005);  // centroid
    EXPECT_NEAR(b1 / n, 1.0 / 3.0, 0.005);
}

TEST(Sampling, StratifiedCoversEachStratumOnce) {
    const int n = 16;
    int counts[4][4] = {};
    for (int k = 0; k < n; ++k) {
        vec2 s = stratified_sample(k, n, vec2(0.999f, 0.001f));
        counts[static_cast<int>(s.x * 4)][static_cast<int>(s.y * 4)]++;
    }
    for (auto& row : counts)
        for (int c : row) EXPECT_EQ(c, 1);
}

}  // namespace
}  // namespace svetlo
