#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/parallel.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / ("svetlo_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir / name;
}

TEST(Srgb, RoundTripsEveryCode) {
    for (int k = 0; k < 256; ++k) {
        float linear = srgb_to_linear(k / 255.0f);
        EXPECT_EQ(linear_to_srgb8(linear), k);
    }
}

TEST(Srgb, KnownValues) {
    EXPECT_NEAR(srgb_to_linear(0.5f), 0.214041f, 1e-5f);  // IEC 61966-2-1
    EXPECT_EQ(linear_to_srgb8(1.0f), 255);
    EXPECT_EQ(linear_to_srgb8(-3.0f), 0);
    EXPECT_EQ(linear_to_srgb8(std::nanf("")), 0);
}

TEST(ImageIo, PfmRoundTripIsExactAndBottomUp) {
    Image image(3, 2);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) image.at(i, j) = Color(i, j, 0.125f * (i + 3 * j));
    fs::path path = temp_file("round.pfm");
    write_image(path, image, PixelMeaning::Radiance, 1.0f, "test");
    TextureImage back = read_texture(path, false, kMaxTextureBytes, "test");
    ASSERT_EQ(back.width(), 3);
    ASSERT_EQ(back.height(), 2);
    EXPECT_FALSE(back.is_8bit());
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) EXPECT_EQ(back.texel(i, j), image.at(i, j));
    // The first row in the file is the bottom row of the image.
    std::ifstream in(path, std::ios::binary);
    std::string magic, dims, scale;
    std::getline(in, magic);
    std::getline(in, dims);
    std::getline(in, scale);
    EXPECT_EQ(magic, "PF");
    EXPECT_EQ(dims, "3 2");
    EXPECT_EQ(scale, "-1.0");
    float first[3];
    in.read(reinterpret_cast<char*>(first), sizeof(first));
    EXPECT_EQ(first[1], 1.0f);  // pixel (0, 1): green channel holds j = 1
}

TEST(ImageIo, ExrRoundTripIsExact) {
    Image image(4, 3);
    for (size_t k = 0; k < image.pixels.size(); ++k)
        image.pixels[k] = Color(k * 0.37f, 1e-3f * k, 17.5f);
    fs::path path = temp_file("round.exr");
    write_image(path, image, PixelMeaning::Radiance, 1.0f, "test");
    TextureImage back = read_texture(path, false, kMaxTextureBytes, "test");
    ASSERT_EQ(back.width(), 4);
    ASSERT_EQ(back.height(), 3);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) EXPECT_EQ(back.texel(i, j), image.at(i, j));
}

TEST(ImageIo, PngIsSrgbWithExposure) {
    Image image(1, 1, Color(0.25f, 0.5f, 2.0f));
    fs::path path = temp_file("exposure.png");
    write_image(path, image, PixelMeaning::Radiance, 2.0f, "test");
    TextureImage back = read_texture(path, false, kMaxTextureBytes, "test");  // codes / 255
    EXPECT_NEAR(back.texel(0, 0).r * 255.0f, linear_to_srgb8(0.5f), 1e-3f);
    EXPECT_NEAR(back.texel(0, 0).g * 255.0f, 255.0f, 1e-3f);
    EXPECT_NEAR(back.texel(0, 0).b * 255.0f, 255.0f, 1e-3f);
}

TEST(Image, TheSrgbEncoderGivesLinearToSrgb8sCodeForEveryFloat) {
    // Its steps are where linear_to_srgb8's code changes; on either side of each, and
    // everywhere else tried, the two agree.
    const Srgb8Encoder encode;
    std::vector<float> tries = {0.0f,
                                -0.0f,
                                1.0f,
                                0.999999f,
                                1e-30f,
                                1.17549435e-38f,
                                -1.0f,
                                std::nanf(""),
                                std::numeric_limits<float>::infinity(),
                                -std::numeric_limits<float>::infinity(),
                                2.0f,
                                1e30f};
    for (unsigned k = 0; k < 1u << 20; ++k)  // a million floats spread over [0, 1.25)
        tries.push_back(static_cast<float>(k) * (1.25f / (1u << 20)));
    uint32_t bits = std::bit_cast<uint32_t>(1e-7f);
    for (int k = 0; k < 1 << 16; ++k, bits += 16127) {  // bit patterns up to past 1
        const float v = std::bit_cast<float>(bits);
        tries.push_back(v);
        tries.push_back(std::nextafter(v, 0.0f));
        tries.push_back(std::nextafter(v, 2.0f));
    }
    bool code_seen[256] = {};
    for (float v : tries) {
        ASSERT_EQ(encode(v), linear_to_srgb8(v)) << v;
        code_seen[encode(v)] = true;
    }
    EXPECT_EQ(std::count(code_seen, code_seen + 256, true), 256);  // every code was tried
}

TEST(ImageIo, JpegHoldsThePngsCodesWithinItsLoss) {
    // The viewer's JPEG (libjpeg-turbo, or stb's encoder without it): a smooth gradient comes
    // back within a few codes of the sRGB codes a PNG would hold.
    Image image(64, 48);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) image.at(x, y) = Color(x / 63.0f, y / 47.0f, 0.25f);
    const std::vector<unsigned char> jpeg = encode_jpeg(image, PixelMeaning::Radiance, 1.0f, 90);
    ASSERT_GT(jpeg.size(), 100u);
    EXPECT_EQ(jpeg[0], 0xff);
    EXPECT_EQ(jpeg[1], 0xd8);  // a JPEG's start-of-image marker
    const fs::path path = temp_file("view.jpg");
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(jpeg.data()),
               static_cast<std::streamsize>(jpeg.size()));
    TextureImage back = read_texture(path, false, kMaxTextureBytes, "test");
    ASSERT_EQ(back.width(), 64);
    ASSERT_EQ(back.height(), 48);
    double error = 0.0;
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 64; ++x) {
            error += std::abs(back.texel(x, y).r * 255.0f - linear_to_srgb8(x / 63.0f));
            error += std::abs(back.texel(x, y).g * 255.0f - linear_to_srgb8(y / 47.0f));
        }
    }
    EXPECT_LT(error / (2 * 64 * 48), 3.0);
}

// The JPEG's rows are made band by band by two threads as libjpeg asks for them: the same
// bytes on one thread and on two, every time, and every row there (a height that is not a
// multiple of the 16-row bands: the last band is short), within the JPEG's loss of the codes.
TEST(ImageIo, JpegRowsMadeBesideTheEncodingAreTheSameOnOneAndTwoThreads) {
    Image image(200, 150);
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < 200; ++x) image.at(x, y) = Color(x / 199.0f, y / 149.0f, 0.5f);
    std::vector<std::vector<unsigned char>> jpegs;
    for (int threads : {1, 2, 1, 2}) {
        with_threads(threads, [&] {
            jpegs.push_back(encode_jpeg(image, PixelMeaning::Radiance, 1.0f, 90));
        });
    }
    for (const std::vector<unsigned char>& jpeg : jpegs) EXPECT_EQ(jpeg, jpegs[0]);
    const fs::path path = temp_file("rows.jpg");
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(jpegs[0].data()),
               static_cast<std::streamsize>(jpegs[0].size()));
    const TextureImage back = read_texture(path, false, kMaxTextureBytes, "test");
    ASSERT_EQ(back.height(), 150);
    // Row by row: a row left unmade would be black, 74 codes or more off below row 10.
    for (int y = 0; y < 150; ++y) {
        double error = 0.0;
        for (int x = 0; x < 200; ++x)
            error += std::abs(back.texel(x, y).g * 255.0f - linear_to_srgb8(y / 149.0f));
        EXPECT_LT(error / 200.0, 6.0) << "row " << y;  // measured: 0.3 to 4.6 (row 0)
    }
}

// An 8-bit file stays 8-bit in memory: three bytes a texel (a float copy took twelve), each
// code decoded through the sRGB curve exactly as the float reader did, or as code / 255.
TEST(ImageIo, PngTexturesKeepTheirCodes) {
    Image image(16, 4);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 16; ++i)
            image.at(i, j) = Color(srgb_to_linear((16 * j + i) / 255.0f), 0.0f, 1.0f);
    fs::path path = temp_file("codes.png");
    write_image(path, image, PixelMeaning::Radiance, 1.0f, "test");
    TextureImage srgb = read_texture(path, true, kMaxTextureBytes, "test");
    TextureImage linear = read_texture(path, false, kMaxTextureBytes, "test");
    EXPECT_TRUE(srgb.is_8bit());
    EXPECT_EQ(srgb.bytes(), 3u * 16u * 4u);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 16; ++i) {
            int code = 16 * j + i;
            EXPECT_EQ(srgb.texel(i, j).r, srgb_to_linear(code / 255.0f));
            EXPECT_EQ(linear.texel(i, j).r, code / 255.0f);
            EXPECT_EQ(srgb.texel(i, j).b, 1.0f);
        }
    }
}

// A file far too short for the texels its header declares is refused before decoding: stb
// pads a truncated TGA to its full size (this 23-byte file, found by fuzzing, declares
// 30463 x 4120 texels and took 1.3 s and 740 MB to read).
TEST(ImageIo, AHeaderThatDeclaresMoreThanTheFileHoldsIsRefused) {
    const unsigned char tga[23] = {0x76, 0x00, 0x0a, 0x32, 0x20, 0x31, 0x28, 0x07,
                                   0xf2, 0x2d, 0x00, 0x41, 0xff, 0x76, 0x18, 0x10,
                                   0x10, 0x52, 0x50, 0x42, 0x38, 0x69, 0x41};
    fs::path path = temp_file("bomb.tga");
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(tga), sizeof tga);
    try {
        read_texture(path, true, kMaxTextureBytes, "test");
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find("30463 x 4120 texels in 23 bytes"), std::string::npos)
            << e.message();
    }
}

// The memory a texture's texels would take is checked from the header, before decoding:
// a 16 x 4 PNG takes 192 bytes at 8 bits, a 16 x 4 PFM 768 bytes at float.
TEST(ImageIo, TexturePastItsMemoryIsRefusedFromTheHeader) {
    Image image(16, 4, Color(0.5f));
    fs::path png = temp_file("budget.png"), pfm = temp_file("budget.pfm");
    write_image(png, image, PixelMeaning::Radiance, 1.0f, "test");
    write_image(pfm, image, PixelMeaning::Radiance, 1.0f, "test");
    EXPECT_NO_THROW(read_texture(png, true, 192, "test"));
    EXPECT_NO_THROW(read_texture(pfm, true, 768, "test"));
    EXPECT_THROW(read_texture(png, true, 191, "test"), Error);
    EXPECT_THROW(read_texture(pfm, true, 767, "test"), Error);
}

TEST(ImageIo, UnknownExtensionAndMissingFolderAreErrors) {
    EXPECT_THROW(image_format_for("out.jpg", "-o"), Error);
    EXPECT_THROW(check_writable("/nonexistent-folder/out.png", "-o"), Error);
    Image image(1, 1);
    EXPECT_THROW(
        write_image("/nonexistent-folder/out.png", image, PixelMeaning::Radiance, 1.0f, "-o"),
        Error);
}

TEST(ImageIo, FailedWriteLeavesTheOldFile) {
    // OpenEXR refuses an empty data window: the write fails after the temporary file was
    // opened, and the file already there must survive unchanged, with no temporary left.
    fs::path path = temp_file("keep.exr");
    { std::ofstream(path) << "old"; }
    EXPECT_THROW(write_image(path, Image(0, 0), PixelMeaning::Radiance, 1.0f, "-o"), Error);
    std::ifstream in(path);
    std::string content;
    in >> content;
    EXPECT_EQ(content, "old");
    int files = 0;
    for (const auto& entry : fs::directory_iterator(path.parent_path())) {
        files += entry.path().string().find(".tmp") != std::string::npos;
    }
    EXPECT_EQ(files, 0);
}

TEST(ImageMetadata, RoundTripsInEveryFormat) {
    Image image(5, 3, Color(0.25f, 0.5f, 1.0f));
    const std::string text = "{\"engine\": \"path\", \"name\": \"caf\u00e9 \u00fc\"}";
    for (const char* name : {"meta.png", "meta.pfm", "meta.exr"}) {
        fs::path path = temp_file(name);
        write_image(path, image, PixelMeaning::Radiance, 1.0f, "-o", text);
        EXPECT_EQ(read_image_metadata(path, "info"), text) << name;
        // The pixels are unchanged by the metadata.
        LoadedImage back = read_image(path, "info");
        ASSERT_EQ(back.image.width, 5);
        EXPECT_NEAR(back.image.at(4, 2).g, 0.5f, 0.004f) << name;
        EXPECT_EQ(back.ldr, std::string(name) == "meta.png");
    }
    // Without metadata: nothing to read back, and no sidecar.
    fs::path plain = temp_file("plain.pfm");
    write_image(plain, image, PixelMeaning::Radiance, 1.0f, "-o");
    EXPECT_EQ(read_image_metadata(plain, "info"), "");
    EXPECT_FALSE(fs::exists(temp_file("plain.pfm.json")));
    fs::path png = temp_file("plain.png");
    write_image(png, image, PixelMeaning::Radiance, 1.0f, "-o");
    EXPECT_EQ(read_image_metadata(png, "info"), "");
}

TEST(ImageMetadata, APfmWrittenWithoutMetadataLeavesNoStaleSidecar) {
    // `svetlo diff -o err.pfm` over a render's err.pfm: the old provenance must not describe
    // the new image.
    fs::path path = temp_file("stale.pfm");
    Image image(2, 2, Color(0.5f));
    write_image(path, image, PixelMeaning::Radiance, 1.0f, "-o", "{\"engine\": \"path\"}");
    ASSERT_FALSE(read_image_metadata(path, "info").empty());
    write_image(path, image, PixelMeaning::Data, 1.0f, "-o");
    EXPECT_EQ(read_image_metadata(path, "info"), "");
    EXPECT_FALSE(fs::exists(temp_file("stale.pfm.json")));
}

}  // namespace
}  // namespace svetlo
