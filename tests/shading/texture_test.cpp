#include "svetlo/shading/texture.h"

#include <gtest/gtest.h>

#include "svetlo/shading/mipmap.h"

namespace svetlo {
namespace {

/// A 4 x 2 image whose texel (i, j) (j from the bottom) holds (i, j, 0).
Image ramp() {
    Image image(4, 2);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) image.at(i, 1 - j) = Color(i, j, 0.0f);
    return image;
}

TEST(Texture, NearestReturnsTexelValues) {
    Image image = ramp();
    EXPECT_EQ(sample_nearest(image, vec2(0.1f, 0.1f), TextureWrap::Repeat), Color(0, 0, 0));
    EXPECT_EQ(sample_nearest(image, vec2(0.9f, 0.9f), TextureWrap::Repeat), Color(3, 1, 0));
    EXPECT_EQ(sample_nearest(image, vec2(0.4f, 0.6f), TextureWrap::Repeat), Color(1, 1, 0));
    EXPECT_EQ(sample_nearest(image, vec2(1.1f, 0.1f), TextureWrap::Repeat), Color(0, 0, 0));
    EXPECT_EQ(sample_nearest(image, vec2(1.1f, 0.1f), TextureWrap::Clamp), Color(3, 0, 0));
}

TEST(Texture, BilinearMatchesTheFormula) {
    Image image = ramp();
    // Between texel centres (1, 0) at u = 0.375 and (2, 0) at 0.625, v at the bottom centre.
    vec2 uv(0.375f + 0.25f * 0.3f, 0.25f + 0.5f * 0.4f);
    Color c = sample_bilinear(image, uv, TextureWrap::Clamp);
    EXPECT_NEAR(c.r, 1.3f, 1e-5f);
    EXPECT_NEAR(c.g, 0.4f, 1e-5f);
    // At a texel centre it is exact.
    EXPECT_EQ(sample_bilinear(image, vec2(0.625f, 0.75f), TextureWrap::Clamp), Color(2, 1, 0));
    // Repeat wraps between the last and first columns.
    EXPECT_NEAR(sample_bilinear(image, vec2(1.0f, 0.25f), TextureWrap::Repeat).r, 1.5f, 1e-5f);
}

TEST(Texture, CheckerAlternates) {
    ColorSource s;
    s.kind = ColorSource::Kind::Checker;
    s.a = Color(1.0f);
    s.b = Color(0.0f);
    s.scale = 2.0f;
    std::vector<Image> none;
    EXPECT_EQ(eval_color(s, vec2(0.1f, 0.1f), none), Color(1.0f));
    EXPECT_EQ(eval_color(s, vec2(0.6f, 0.1f), none), Color(0.0f));
    EXPECT_EQ(eval_color(s, vec2(0.6f, 0.6f), none), Color(1.0f));
    EXPECT_EQ(eval_color(s, vec2(-0.1f, 0.1f), none), Color(0.0f));
}

/// 64 x 64 texels of vertical stripes two texels wide: 0, 0, 1, 1, 0, 0, ... along u,
/// constant along v.
Image stripes() {
    Image image(64, 64);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) image.at(i, j) = Color((i / 2) % 2 == 1 ? 1.0f : 0.0f);
    return image;
}

TEST(Texture, AnisotropicKeepsTheDetailOfTheShortAxis) {
    // A footprint one texel along u and sixteen along v (a floor seen at a grazing angle):
    // over it the texture is constant along v, so the right answer at the centre of a texel
    // is that texel. Trilinear takes the level of the long axis (16 texels: the stripes
    // averaged away); anisotropic takes sixteen probes at level 0 along v.
    MipChain chain = build_mip_chain(stripes());
    vec2 dx(1.0f / 64.0f, 0.0f), dy(0.0f, 16.0f / 64.0f);
    for (int i : {2, 3, 6, 7, 10}) {
        vec2 uv((static_cast<float>(i) + 0.5f) / 64.0f, 0.37f);
        float expected = (i / 2) % 2 == 1 ? 1.0f : 0.0f;
        Color a = sample_anisotropic(chain, uv, dx, dy, 16, TextureWrap::Repeat);
        Color t = sample_trilinear(chain, uv, mip_level(chain, dx, dy), TextureWrap::Repeat);
        EXPECT_NEAR(a.r, expected, 1e-5f) << i;
        EXPECT_NEAR(t.r, 0.5f, 0.05f) << i;
    }
    // The probe budget bounds it: four probes reach level log2(16 / 4) = 2, where texels are
    // four wide and the stripes average out too.
    vec2 uv(3.5f / 64.0f, 0.37f);
    EXPECT_NEAR(sample_anisotropic(chain, uv, dx, dy, 4, TextureWrap::Repeat).r, 0.5f, 0.05f);
}

TEST(Texture, AnisotropicIsTrilinearOnARoundFootprintAndKeepsTheMean) {
    MipChain chain = build_mip_chain(stripes());
    // Round footprints (any orientation): exactly the trilinear lookup.
    for (float angle : {0.0f, 0.4f, 1.1f}) {
        vec2 dx = 5.0f / 64.0f * vec2(std::cos(angle), std::sin(angle));
        vec2 dy = 5.0f / 64.0f * vec2(-std::sin(angle), std::cos(angle));
        vec2 uv(0.3f, 0.6f);
        EXPECT_EQ(sample_anisotropic(chain, uv, dx, dy, 16, TextureWrap::Repeat),
                  sample_trilinear(chain, uv, mip_level(chain, dx, dy), TextureWrap::Repeat));
    }
    // A stretched, rotated footprint: averaged over the texture, the stripes' mean, 1/2.
    vec2 dx = vec2(6.0f, 2.0f) / 64.0f, dy = vec2(-0.2f, 0.6f) / 64.0f;
    double sum = 0.0;
    const int n = 97;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            vec2 uv((static_cast<float>(i) + 0.5f) / n, (static_cast<float>(j) + 0.5f) / n);
            sum += sample_anisotropic(chain, uv, dx, dy, 16, TextureWrap::Repeat).r;
        }
    }
    EXPECT_NEAR(sum / (n * n), 0.5, 0.01);
}

}  // namespace
}  // namespace svetlo
