// PNG and JPEG textures decoded by libspng and libjpeg-turbo (core/rgb8_decode.h) against
// stb_image, which decodes them where those libraries are absent (the web) and every other
// format: the same codes from every kind of PNG, a JPEG within a code or two, a damaged file
// refused as stb refuses it; and texture copies share their texels until one is written.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "svetlo/core/image_io.h"
#include "svetlo/core/rgb8_decode.h"
#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

void put32(std::vector<unsigned char>& out, uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<unsigned char>(v >> s));
}

void chunk(std::vector<unsigned char>& out, const char* type,
           const std::vector<unsigned char>& data) {
    put32(out, static_cast<uint32_t>(data.size()));
    std::vector<unsigned char> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    out.insert(out.end(), body.begin(), body.end());
    put32(out, static_cast<uint32_t>(crc32(0, body.data(), static_cast<uInt>(body.size()))));
}

/// A PNG (PNG Third Edition) of `w` x `h` texels of colour type `type` and bit depth `depth`,
/// its rows of random samples (palette indices below `palette` entries), unfiltered.
std::vector<unsigned char> random_png(int w, int h, int type, int depth, uint64_t seed) {
    const int channels = type == 0 || type == 3 ? 1 : type == 2 ? 3 : type == 4 ? 2 : 4;
    const size_t row = (static_cast<size_t>(w) * channels * depth + 7) / 8;
    Rng rng(seed, 1);
    std::vector<unsigned char> raw;
    const int entries = type == 3 ? 1 << depth : 0;
    for (int j = 0; j < h; ++j) {
        raw.push_back(0);  // filter: none
        for (size_t b = 0; b < row; ++b)
            raw.push_back(static_cast<unsigned char>(rng.next_float() * 256.0f));
    }
    std::vector<unsigned char> packed(compressBound(static_cast<uLong>(raw.size())));
    uLongf packed_size = static_cast<uLongf>(packed.size());
    compress(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()));
    packed.resize(packed_size);
    std::vector<unsigned char> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<unsigned char> header;
    put32(header, static_cast<uint32_t>(w));
    put32(header, static_cast<uint32_t>(h));
    for (int v : {depth, type, 0, 0, 0}) header.push_back(static_cast<unsigned char>(v));
    chunk(out, "IHDR", header);
    if (entries > 0) {
        std::vector<unsigned char> palette;
        for (int k = 0; k < 3 * entries; ++k)
            palette.push_back(static_cast<unsigned char>(rng.next_float() * 256.0f));
        chunk(out, "PLTE", palette);
    }
    chunk(out, "IDAT", packed);
    chunk(out, "IEND", {});
    return out;
}

/// stb_image's RGB codes of an image in memory.
std::vector<unsigned char> stb_codes(const std::vector<unsigned char>& file) {
    int w = 0, h = 0, n = 0;
    std::unique_ptr<unsigned char, void (*)(void*)> data(
        stbi_load_from_memory(file.data(), static_cast<int>(file.size()), &w, &h, &n, 3),
        stbi_image_free);
    if (!data) return {};
    return std::vector<unsigned char>(data.get(), data.get() + 3 * static_cast<size_t>(w) * h);
}

/// The codes a texture read as linear data holds (code / 255 is exact in its table).
std::vector<unsigned char> texture_codes(const TextureImage& t) {
    std::vector<unsigned char> codes;
    for (int j = 0; j < t.height(); ++j)
        for (int i = 0; i < t.width(); ++i)
            for (int c = 0; c < 3; ++c)
                codes.push_back(static_cast<unsigned char>(std::lround(t.texel(i, j)[c] * 255.0f)));
    return codes;
}

TEST(TextureDecode, EveryKindOfPngGivesStbsCodes) {
    // Grey of 1, 8 and 16 bits, RGB of 8 and 16, palettes of 4 and 8 bits, grey and alpha,
    // RGBA of 8 and 16 bits; widths that leave a partial byte at the end of a row.
    const int kinds[][2] = {{0, 1}, {0, 8}, {0, 16}, {2, 8}, {2, 16},
                            {3, 4}, {3, 8}, {4, 8},  {6, 8}, {6, 16}};
    uint64_t seed = 1;
    for (const auto& [type, depth] : kinds) {
        const std::vector<unsigned char> png = random_png(37, 11, type, depth, seed++);
        const std::vector<unsigned char> expected = stb_codes(png);
        ASSERT_EQ(expected.size(), 3u * 37 * 11) << type << " " << depth;
        std::vector<unsigned char> decoded;
        EXPECT_EQ(decode_rgb8(png.data(), png.size(), 37, 11, decoded), png_decoded_by_libspng());
        if (png_decoded_by_libspng()) {
            EXPECT_EQ(decoded, expected) << "type " << type << ", depth " << depth;
        }
        const TextureImage t =
            decode_texture(png.data(), png.size(), TexelMeaning::Linear, kMaxTextureBytes);
        EXPECT_EQ(texture_codes(t), expected) << "type " << type << ", depth " << depth;
    }
}

TEST(TextureDecode, AJpegGivesStbsCodesWithinTwo) {
    std::vector<unsigned char> rgb;
    for (int j = 0; j < 48; ++j)
        for (int i = 0; i < 40; ++i)
            for (int v : {5 * i, 5 * j, 128 + 60 * ((i / 8 + j / 8) % 2)})
                rgb.push_back(static_cast<unsigned char>(v));
    std::vector<unsigned char> jpeg;
    stbi_write_jpg_to_func(
        [](void* out, void* data, int size) {
            auto* bytes = static_cast<const unsigned char*>(data);
            static_cast<std::vector<unsigned char>*>(out)->insert(
                static_cast<std::vector<unsigned char>*>(out)->end(), bytes, bytes + size);
        },
        &jpeg, 40, 48, 3, rgb.data(), 90);
    const std::vector<unsigned char> expected = stb_codes(jpeg);
    ASSERT_EQ(expected.size(), rgb.size());
    std::vector<unsigned char> decoded;
    EXPECT_EQ(decode_rgb8(jpeg.data(), jpeg.size(), 40, 48, decoded), jpeg_decoded_by_libjpeg());
    const TextureImage t =
        decode_texture(jpeg.data(), jpeg.size(), TexelMeaning::Linear, kMaxTextureBytes);
    const std::vector<unsigned char> codes = texture_codes(t);
    ASSERT_EQ(codes.size(), expected.size());
    int worst = 0;
    for (size_t k = 0; k < codes.size(); ++k)
        worst = std::max(worst, std::abs(codes[k] - expected[k]));
    EXPECT_LE(worst, 2);  // their IDCTs and chroma upsampling round apart
}

TEST(TextureDecode, ADamagedPngIsRefusedAsStbRefusesIt) {
    std::vector<unsigned char> png = random_png(16, 16, 2, 8, 3);
    png.resize(png.size() - 40);  // cut inside the compressed data
    std::vector<unsigned char> decoded;
    EXPECT_FALSE(decode_rgb8(png.data(), png.size(), 16, 16, decoded));
    EXPECT_TRUE(decoded.empty());
    EXPECT_THROW(decode_texture(png.data(), png.size(), TexelMeaning::Linear, kMaxTextureBytes),
                 std::runtime_error);
}

TEST(TextureDecode, CopiesShareTheirTexelsUntilOneIsWritten) {
    TextureImage a(2, 1, {10, 20, 30, 40, 50, 60}, false);
    TextureImage b = a;
    EXPECT_TRUE(b.same_texels(a));
    b.set_texel(0, 0, Color(1.0f));
    EXPECT_EQ(texture_codes(b), (std::vector<unsigned char>{255, 255, 255, 40, 50, 60}));
    EXPECT_EQ(texture_codes(a), (std::vector<unsigned char>{10, 20, 30, 40, 50, 60}));
    EXPECT_FALSE(b.same_texels(a));
}

}  // namespace
}  // namespace svetlo
