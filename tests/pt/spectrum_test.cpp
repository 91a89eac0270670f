// The wavelengths of dispersion (pt/spectrum.h): Cauchy's law through the Abbe number, and
// the weights that turn one wavelength into RGB.
#include "svetlo/pt/spectrum.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

TEST(Spectrum, CauchyIorGivesTheIorAndAbbeNumberBack) {
    // BK7: n_d = 1.5168, V_d = 64.17.
    const float nd = 1.5168f, v = 64.17f;
    EXPECT_NEAR(cauchy_ior(nd, v, 587.6f), nd, 1e-6f);
    float nf = cauchy_ior(nd, v, 486.1f), nc = cauchy_ior(nd, v, 656.3f);
    EXPECT_NEAR((nd - 1.0f) / (nf - nc), v, 1e-3f * v);
    EXPECT_GT(cauchy_ior(nd, v, 400.0f), cauchy_ior(nd, v, 700.0f));  // blue bends more
    // BK7's measured index at 435.8 nm (g line) is 1.5267: Cauchy's two terms come within 1e-3.
    EXPECT_NEAR(cauchy_ior(nd, v, 435.8f), 1.5267f, 1e-3f);
}

TEST(Spectrum, WeightsAverageToWhite) {
    WavelengthWeights w;
    glm::dvec3 sum(0.0);
    const int n = 100000;
    for (int k = 0; k < n; ++k)
        sum += glm::dvec3(w.weight(WavelengthWeights::lambda_of((k + 0.5f) / n)));
    sum /= n;
    EXPECT_NEAR(sum.x, 1.0, 1e-4);
    EXPECT_NEAR(sum.y, 1.0, 1e-4);
    EXPECT_NEAR(sum.z, 1.0, 1e-4);
}

TEST(Spectrum, WeightsFollowTheRainbow) {
    WavelengthWeights w;
    Color blue = w.weight(450.0f), green = w.weight(530.0f), red = w.weight(650.0f);
    EXPECT_GT(blue.b, 4.0f * blue.r);
    EXPECT_GT(green.g, 2.0f * green.r);
    EXPECT_GT(green.g, 2.0f * green.b);
    EXPECT_GT(red.r, 4.0f * red.g);
    for (float l = kLambdaMin; l <= kLambdaMax; l += 1.0f) {
        Color c = w.weight(l);
        ASSERT_GE(std::min({c.r, c.g, c.b}), 0.0f) << l;
    }
    // The matching functions' peaks: y at 555 nm (0.98 of a maximum near 1), x at 600 nm.
    EXPECT_NEAR(cie_xyz(555.0f).y, 1.0f, 0.03f);
    EXPECT_NEAR(cie_xyz(599.8f).x, 1.05f, 0.03f);
}

}  // namespace
}  // namespace svetlo
