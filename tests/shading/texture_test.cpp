#include <gtest/gtest.h>

#include "svetlo/shading/texture.h"

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

}  // namespace
}  // namespace svetlo
