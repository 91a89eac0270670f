#include "svetlo/shading/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "svetlo/shading/mipmap.h"

namespace svetlo {
namespace {

/// A 4 x 2 image whose texel (i, j) (j from the bottom) holds (i, j, 0).
TextureImage ramp() {
    Image image(4, 2);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) image.at(i, 1 - j) = Color(i, j, 0.0f);
    return TextureImage(std::move(image));
}

TEST(Texture, NearestReturnsTexelValues) {
    TextureImage image = ramp();
    EXPECT_EQ(sample_nearest(image, vec2(0.1f, 0.1f), TextureWrap::Repeat), Color(0, 0, 0));
    EXPECT_EQ(sample_nearest(image, vec2(0.9f, 0.9f), TextureWrap::Repeat), Color(3, 1, 0));
    EXPECT_EQ(sample_nearest(image, vec2(0.4f, 0.6f), TextureWrap::Repeat), Color(1, 1, 0));
    EXPECT_EQ(sample_nearest(image, vec2(1.1f, 0.1f), TextureWrap::Repeat), Color(0, 0, 0));
    EXPECT_EQ(sample_nearest(image, vec2(1.1f, 0.1f), TextureWrap::Clamp), Color(3, 0, 0));
}

TEST(Texture, BilinearMatchesTheFormula) {
    TextureImage image = ramp();
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

// Mirror reads the texture forward on [0, 1] and backward on [1, 2] and [-1, 0], the edge
// texel twice at each seam (GL's and glTF's MIRRORED_REPEAT), for every size, below 0 and past
// the end: column i of a one-row texture holds i.
TEST(Texture, MirrorReadsEveryOtherPeriodBackward) {
    for (int n = 1; n <= 9; ++n) {
        Image row(n, 1);
        for (int i = 0; i < n; ++i) row.at(i, 0) = Color(static_cast<float>(i));
        const TextureImage image(std::move(row));
        const auto mirrored = [n](int i) {
            const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
            return m < n ? m : 2 * n - 1 - m;
        };
        for (int i = -3 * n - 1; i <= 3 * n + 1; ++i) {
            const float u = (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
            EXPECT_EQ(sample_nearest(image, vec2(u, 0.5f), TextureWrap::Mirror).r,
                      static_cast<float>(mirrored(i)))
                << "n " << n << ", i " << i;
            const float between =
                sample_bilinear(image,
                                vec2((static_cast<float>(i) + 1.0f) / static_cast<float>(n), 0.5f),
                                TextureWrap::Mirror)
                    .r;
            EXPECT_FLOAT_EQ(between, 0.5f * static_cast<float>(mirrored(i) + mirrored(i + 1)))
                << "n " << n << ", i " << i;
        }
    }
    // Texel 3 of 4 at u = 0.875, read backward at 1.125 and at -0.875.
    const TextureImage image = ramp();
    EXPECT_EQ(sample_nearest(image, vec2(1.125f, 0.25f), TextureWrap::Mirror), Color(3, 0, 0));
    EXPECT_EQ(sample_nearest(image, vec2(-0.875f, 0.25f), TextureWrap::Mirror), Color(3, 0, 0));
    // At the seam u = 1 bilinear filtering blends the last texel with itself, not with the first.
    EXPECT_EQ(sample_bilinear(image, vec2(1.0f, 0.25f), TextureWrap::Mirror), Color(3, 0, 0));
}

// A coordinate far outside [0, 1] reads the texel it wraps to: 300000.125 texture widths on a
// texture 8192 wide is texel 1024 repeated, backward (8191 - 1024) mirrored, the last
// clamped. Times the width it is past the range of int, where the index was undefined.
TEST(Texture, FarCoordinatesReadTheTexelTheyWrapTo) {
    Image row(8192, 1);
    for (int i = 0; i < 8192; ++i) row.at(i, 0) = Color(static_cast<float>(i));
    const TextureImage image(std::move(row));
    const vec2 far(300000.125f + 0.5f / 8192.0f, 0.5f);
    EXPECT_EQ(sample_nearest(image, far, TextureWrap::Repeat).r, 1024.0f);
    EXPECT_EQ(sample_nearest(image, far, TextureWrap::Mirror).r, 1024.0f);
    EXPECT_EQ(sample_nearest(image, far + vec2(1.0f, 0.0f), TextureWrap::Mirror).r,
              8191.0f - 1024.0f);
    EXPECT_EQ(sample_nearest(image, far, TextureWrap::Clamp).r, 8191.0f);
    EXPECT_EQ(sample_nearest(image, -far, TextureWrap::Clamp).r, 0.0f);
}

TEST(Texture, EachAxisWrapsByItsOwnMode) {
    const TextureImage image = ramp();
    // u mirrored, v clamped; u repeated, v mirrored.
    const TextureWraps mirror_clamp(TextureWrap::Mirror, TextureWrap::Clamp);
    EXPECT_EQ(sample_nearest(image, vec2(1.125f, 1.75f), mirror_clamp), Color(3, 1, 0));
    EXPECT_EQ(sample_nearest(image, vec2(1.125f, -0.75f), mirror_clamp), Color(3, 0, 0));
    const TextureWraps repeat_mirror(TextureWrap::Repeat, TextureWrap::Mirror);
    EXPECT_EQ(sample_nearest(image, vec2(1.125f, 1.25f), repeat_mirror), Color(0, 1, 0));
    EXPECT_EQ(sample_nearest(image, vec2(1.125f, 1.75f), repeat_mirror), Color(0, 0, 0));
}

// Repeat wraps texel indices modulo the size, below 0 and past the end alike, for sizes that
// are powers of two and sizes that are not: column i of a one-row texture holds i.
TEST(Texture, RepeatWrapsEveryIndexModuloTheSize) {
    for (int n = 1; n <= 9; ++n) {
        Image row(n, 1);
        for (int i = 0; i < n; ++i) row.at(i, 0) = Color(static_cast<float>(i));
        const TextureImage image(std::move(row));
        for (int i = -3 * n - 1; i <= 3 * n + 1; ++i) {
            const float u = (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
            const int expected = ((i % n) + n) % n;
            EXPECT_EQ(sample_nearest(image, vec2(u, 0.5f), TextureWrap::Repeat).r,
                      static_cast<float>(expected))
                << "n " << n << ", i " << i;
            // Bilinear between texel i and i + 1 (both wrapped), halfway.
            const float between =
                sample_bilinear(image,
                                vec2((static_cast<float>(i) + 1.0f) / static_cast<float>(n), 0.5f),
                                TextureWrap::Repeat)
                    .r;
            EXPECT_FLOAT_EQ(between, 0.5f * static_cast<float>(expected + (expected + 1) % n))
                << "n " << n << ", i " << i;
        }
    }
}

TEST(Texture, CheckerAlternates) {
    ColorSource s;
    s.kind = ColorSource::Kind::Checker;
    s.a = Color(1.0f);
    s.b = Color(0.0f);
    s.scale = 2.0f;
    std::vector<TextureImage> none;
    EXPECT_EQ(eval_color(s, vec2(0.1f, 0.1f), none), Color(1.0f));
    EXPECT_EQ(eval_color(s, vec2(0.6f, 0.1f), none), Color(0.0f));
    EXPECT_EQ(eval_color(s, vec2(0.6f, 0.6f), none), Color(1.0f));
    EXPECT_EQ(eval_color(s, vec2(-0.1f, 0.1f), none), Color(0.0f));
}

/// 64 x 64 texels of vertical stripes two texels wide: 0, 0, 1, 1, 0, 0, ... along u,
/// constant along v.
TextureImage stripes() {
    Image image(64, 64);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) image.at(i, j) = Color((i / 2) % 2 == 1 ? 1.0f : 0.0f);
    return TextureImage(std::move(image));
}

// Storing a decoded code gives the code back, for all 256 codes in both encodings; values
// outside [0, 1] and NaN clip to the end codes.
TEST(Texture, EightBitStorageRoundTripsEveryCode) {
    for (bool srgb : {true, false}) {
        for (int k = 0; k < 256; ++k) {
            auto c = static_cast<unsigned char>(k);
            TextureImage t(1, 1, {c, c, c}, srgb);
            Color decoded = t.texel(0, 0);
            t.set_texel(0, 0, decoded);
            EXPECT_EQ(t.texel(0, 0), decoded) << k;
        }
        TextureImage t(1, 1, {0, 0, 0}, srgb);
        t.set_texel(0, 0, Color(-1.0f, 7.0f, std::nanf("")));
        EXPECT_EQ(t.texel(0, 0), Color(0.0f, 1.0f, 0.0f));
        t.set_texel(0, 0, Color(std::numeric_limits<float>::infinity(), 0.0f, -0.0f));
        EXPECT_EQ(t.texel(0, 0), Color(1.0f, 0.0f, 0.0f));
    }
}

// A value is stored as its nearest code: from the halfway point between codes k and k + 1
// (in the encoded space) up, k + 1; the float just below it, k. Every boundary, both
// encodings.
TEST(Texture, EightBitStorageRoundsAtTheHalfwayPoints) {
    for (bool srgb : {true, false}) {
        TextureImage codes(1, 1, {0, 0, 0}, srgb);
        for (int k = 0; k < 255; ++k) {
            const float half = (static_cast<float>(k) + 0.5f) / 255.0f;
            const float at = srgb ? srgb_to_linear(half) : half;
            const float below = std::nextafter(at, 0.0f);
            codes.set_texel(0, 0, Color(at, below, at));
            TextureImage expected(1, 1,
                                  {static_cast<unsigned char>(k + 1), static_cast<unsigned char>(k),
                                   static_cast<unsigned char>(k + 1)},
                                  srgb);
            EXPECT_EQ(codes.texel(0, 0), expected.texel(0, 0)) << k << (srgb ? " srgb" : "");
        }
    }
}

// 8-bit textures keep 8-bit mip levels (a GPU's glGenerateMipmap), averaged in linear RGB:
// each level's texel is the code nearest the mean of the four above it.
TEST(Texture, EightBitMipLevelsStayEightBitAndAverageInLinear) {
    const int n = 8;
    std::vector<unsigned char> codes(3 * n * n);
    for (size_t k = 0; k < codes.size(); ++k) codes[k] = static_cast<unsigned char>((k * 37) % 256);
    for (bool srgb : {true, false}) {
        TextureImage texture(n, n, codes, srgb);
        MipChain chain = build_mip_chain(texture);
        ASSERT_EQ(chain.count(), 4);
        for (int l = 1; l < chain.count(); ++l) {
            const TextureImage& up = chain.level(l - 1);
            const TextureImage& level = chain.level(l);
            EXPECT_TRUE(level.is_8bit());
            EXPECT_EQ(level.bytes(), 3u * static_cast<size_t>(level.width() * level.height()));
            for (int j = 0; j < level.height(); ++j) {
                for (int i = 0; i < level.width(); ++i) {
                    Color mean =
                        0.25f * (up.texel(2 * i, 2 * j) + up.texel(2 * i + 1, 2 * j) +
                                 up.texel(2 * i, 2 * j + 1) + up.texel(2 * i + 1, 2 * j + 1));
                    for (int c = 0; c < 3; ++c) {
                        // Within half a code of the mean, in the code's own encoding.
                        float code =
                            srgb ? linear_to_srgb(level.texel(i, j)[c]) : level.texel(i, j)[c];
                        float want = srgb ? linear_to_srgb(mean[c]) : mean[c];
                        EXPECT_NEAR(code, want, 0.5f / 255.0f + 1e-6f) << l << " " << i << j;
                    }
                }
            }
        }
    }
}

TEST(Texture, AnisotropicKeepsTheDetailOfTheShortAxis) {
    // A footprint one texel along u and sixteen along v (a floor seen at a grazing angle):
    // over it the texture is constant along v, so the right answer at the centre of a texel
    // is that texel. Trilinear takes the level of the long axis (16 texels: the stripes
    // averaged away); anisotropic takes sixteen probes at level 0 along v.
    TextureImage texture = stripes();
    MipChain chain = build_mip_chain(texture);
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
    TextureImage texture = stripes();
    MipChain chain = build_mip_chain(texture);
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

// Colours of many points at once (eval_colors, the rasterizer's runs) are the colours one by
// one, bit for bit: every kind of source and filter, footprints from none to the whole texture.
TEST(Texture, ColoursOfManyPointsAreTheColoursOneByOne) {
    std::vector<unsigned char> codes(3 * 32 * 16);
    for (size_t k = 0; k < codes.size(); ++k) codes[k] = static_cast<unsigned char>((k * 53) % 256);
    const std::vector<TextureImage> textures = {stripes(), TextureImage(32, 16, codes, true)};
    const std::vector<MipChain> mips = {build_mip_chain(textures[0]), build_mip_chain(textures[1])};
    std::vector<ColorSource> sources = {ColorSource::constant(Color(0.2f, 0.3f, 0.4f))};
    ColorSource checker;
    checker.kind = ColorSource::Kind::Checker;
    checker.scale = 3.0f;
    sources.push_back(checker);
    for (int texture : {0, 1}) {
        for (TextureFilter filter : {TextureFilter::Nearest, TextureFilter::Bilinear,
                                     TextureFilter::Trilinear, TextureFilter::Anisotropic}) {
            for (TextureWraps wrap :
                 {TextureWraps(TextureWrap::Repeat), TextureWraps(TextureWrap::Clamp),
                  TextureWraps(TextureWrap::Mirror, TextureWrap::Clamp)}) {
                ColorSource s;
                s.kind = ColorSource::Kind::Image;
                s.texture = texture;
                s.filter = filter;
                s.wrap = wrap;
                sources.push_back(s);
            }
        }
    }
    // 150 points (more than one chunk of 64), their footprints 0 to 4 texture widths.
    std::vector<vec2> uv, dx, dy;
    for (int k = 0; k < 150; ++k) {
        const auto t = static_cast<float>(k);
        uv.emplace_back(std::sin(t) * 1.7f, std::cos(1.3f * t) * 2.1f);
        const float size = k % 7 == 0 ? 0.0f : std::pow(2.0f, static_cast<float>(k % 13) - 10.0f);
        dx.emplace_back(size, 0.3f * size);
        dy.emplace_back(-0.2f * size, size * static_cast<float>(k % 3));
    }
    for (const ColorSource& s : sources) {
        for (const std::vector<MipChain>* chains :
             {&mips, static_cast<const std::vector<MipChain>*>(nullptr)}) {
            const TextureLookup lookup{textures, chains};
            std::vector<Color> many(uv.size());
            eval_colors(s, uv.data(), dx.data(), dy.data(), uv.size(), lookup, many.data());
            for (size_t k = 0; k < uv.size(); ++k) {
                TextureLookup one = lookup;
                one.duv_dx = dx[k];
                one.duv_dy = dy[k];
                ASSERT_EQ(many[k], eval_color(s, uv[k], one)) << "point " << k;
            }
        }
    }
}

}  // namespace
}  // namespace svetlo
