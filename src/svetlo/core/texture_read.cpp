// Reading textures: PFM, OpenEXR, stb's 8-bit and HDR formats, WebP (libwebp, where the
// build has it), and PNG and JPEG colours through libspng and libjpeg-turbo where it has them
// (rgb8_decode.h) into TextureImage, each size checked from its header before anything is
// decoded; colour, data or coverage texels (image_io.h, read_texture). The writing of images
// and the reading of films and their metadata stay in image_io.cpp.
#ifdef SVETLO_HAS_OPENEXR
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#endif
#include <stb_image.h>
#ifdef SVETLO_HAS_WEBP
#include <webp/decode.h>
#endif

#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/image_signature.h"
#include "svetlo/core/input_file.h"
#include "svetlo/core/rgb8_decode.h"

namespace svetlo {
namespace fs = std::filesystem;

namespace {

constexpr uintmax_t kMaxTexelsPerByte = 16384;

/// Refuses, from its header, a texture whose texels would take more than `max_bytes`.
void check_texture_size(long long w, long long h, size_t bytes_per_texel, size_t max_bytes) {
    size_t bytes = static_cast<size_t>(w) * static_cast<size_t>(h) * bytes_per_texel;
    if (w > 65536 || h > 65536 || bytes > max_bytes) {
        auto mib = [](size_t b) { return std::to_string((b + (size_t{1} << 20) - 1) >> 20); };
        throw std::runtime_error(
            "is " + std::to_string(w) + " x " + std::to_string(h) + " texels, which need " +
            mib(bytes) + " MiB in memory, more than the " + mib(max_bytes) +
            " MiB left for it (a texture may take " + mib(kMaxTextureBytes) +
            " MiB, a scene's textures " + mib(kMaxSceneTextureBytes) + " MiB)");
    }
}

TextureImage read_pfm(const fs::path& path, size_t max_bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(std::strerror(errno));
    std::string magic;
    long long w = 0, h = 0;
    double scale = 0.0;
    in >> magic >> w >> h >> scale;
    in.get();
    int channels = magic == "PF" ? 3 : magic == "Pf" ? 1 : 0;
    if (channels == 0 || !in || w <= 0 || h <= 0 || scale == 0.0) {
        throw std::runtime_error("not a PFM file");
    }
    if (scale > 0.0) throw std::runtime_error("big-endian PFM is not supported");
    check_texture_size(w, h, sizeof(Color), max_bytes);
    Image image(static_cast<int>(w), static_cast<int>(h));
    std::vector<float> row(static_cast<size_t>(w) * channels);
    for (long long j = h - 1; j >= 0; --j) {
        in.read(reinterpret_cast<char*>(row.data()),
                static_cast<std::streamsize>(row.size() * sizeof(float)));
        if (!in) throw std::runtime_error("truncated PFM file");
        for (long long i = 0; i < w; ++i) {
            Color& p = image.at(static_cast<int>(i), static_cast<int>(j));
            p = channels == 3 ? Color(row[3 * i], row[3 * i + 1], row[3 * i + 2]) : Color(row[i]);
        }
    }
    return TextureImage(std::move(image));
}

TextureImage read_exr(const fs::path& path, size_t max_bytes) {
#ifndef SVETLO_HAS_OPENEXR
    (void)path, (void)max_bytes;
    throw std::runtime_error("OpenEXR is not in this build: use .pfm or .hdr");
#else
    Imf::InputFile file(path.c_str());
    Imath::Box2i window = file.header().dataWindow();
    long long w = static_cast<long long>(window.max.x) - window.min.x + 1;
    long long h = static_cast<long long>(window.max.y) - window.min.y + 1;
    if (w <= 0 || h <= 0) throw std::runtime_error("bad EXR size");
    check_texture_size(w, h, sizeof(Color), max_bytes);
    Image image(static_cast<int>(w), static_cast<int>(h));
    Imf::FrameBuffer frame;
    char* base = reinterpret_cast<char*>(image.pixels.data()) -
                 (static_cast<ptrdiff_t>(window.min.x) + static_cast<ptrdiff_t>(window.min.y) * w) *
                     static_cast<ptrdiff_t>(sizeof(Color));
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Color),
                                          sizeof(Color) * static_cast<size_t>(w), 1, 1, 0.0));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return TextureImage(std::move(image));
#endif
}

}  // namespace

std::vector<unsigned char> coverage_codes(const unsigned char* data, int n, size_t texels) {
    const int channel = n == 2 || n == 4 ? n - 1 : 0;
    std::vector<unsigned char> codes(3 * texels);
    for (size_t k = 0; k < texels; ++k)
        codes[3 * k] = codes[3 * k + 1] = codes[3 * k + 2] =
            data[k * static_cast<size_t>(n) + channel];
    return codes;
}

bool reads_webp() {
#ifdef SVETLO_HAS_WEBP
    return true;
#else
    return false;
#endif
}

bool reads_exr() {
#ifdef SVETLO_HAS_OPENEXR
    return true;
#else
    return false;
#endif
}

namespace {

/// Refuses a header that declares more texels than any compression packs into `size` bytes:
/// a truncated or forged file, which a decoder would pad to the full size (a 23-byte TGA of
/// 30463 x 4120 texels took 1.3 s and 740 MB, found by fuzzing). No format read here packs
/// more than 16384 texels into a byte (deflate's limit is 1032:1, times 8 texels a byte for
/// 1-bit PNGs).
void check_texels_per_byte(int w, int h, uintmax_t size) {
    const auto texels = static_cast<uintmax_t>(w) * static_cast<uintmax_t>(h);
    if (texels > kMaxTexelsPerByte * size)
        throw std::runtime_error("declares " + std::to_string(w) + " x " + std::to_string(h) +
                                 " texels in " + std::to_string(size) +
                                 " bytes, more than any compression holds: the file is "
                                 "truncated or damaged");
}

/// An 8-bit texture's codes: RGB for a colour, coverage_codes for coverage.
TextureImage texture_of_codes(const unsigned char* data, int w, int h, int n, bool srgb,
                              bool coverage) {
    const size_t texels = static_cast<size_t>(w) * static_cast<size_t>(h);
    if (coverage) return TextureImage(w, h, coverage_codes(data, n, texels), false);
    return TextureImage(w, h, std::vector<unsigned char>(data, data + 3 * texels), srgb);
}

#ifdef SVETLO_HAS_WEBP
TextureImage decode_webp(const unsigned char* bytes, size_t size, bool srgb, size_t max_bytes,
                         bool coverage) {
    WebPBitstreamFeatures features;
    if (WebPGetFeatures(bytes, size, &features) != VP8_STATUS_OK)
        throw std::runtime_error("not a WebP image libwebp reads");
    const int w = features.width, h = features.height;
    check_texture_size(w, h, 3, max_bytes);
    check_texels_per_byte(w, h, size);
    const int n = coverage && features.has_alpha ? 4 : 3;
    int dw = 0, dh = 0;
    std::unique_ptr<uint8_t, void (*)(void*)> data(
        n == 4 ? WebPDecodeRGBA(bytes, size, &dw, &dh) : WebPDecodeRGB(bytes, size, &dw, &dh),
        WebPFree);
    if (!data || dw != w || dh != h) throw std::runtime_error("the WebP image does not decode");
    return texture_of_codes(data.get(), w, h, n, srgb, coverage);
}
#endif

}  // namespace

TextureImage decode_texture(const unsigned char* bytes, size_t size, TexelMeaning meaning,
                            size_t max_bytes) {
    const bool srgb = meaning == TexelMeaning::Srgb, coverage = meaning == TexelMeaning::Coverage;
    if (is_webp(bytes, size)) {
#ifdef SVETLO_HAS_WEBP
        return decode_webp(bytes, size, srgb, max_bytes, coverage);
#else
        throw std::runtime_error("a WebP image, and this build of svetlo has no libwebp");
#endif
    }
    const auto length = static_cast<int>(std::min<size_t>(size, INT32_MAX));
    int w = 0, h = 0, n = 0;
    if (size == 0 || !stbi_info_from_memory(bytes, length, &w, &h, &n))
        throw std::runtime_error(size == 0 ? "no data" : stbi_failure_reason());
    check_texture_size(w, h, 3, max_bytes);
    check_texels_per_byte(w, h, size);
    if (std::vector<unsigned char> codes; !coverage && decode_rgb8(bytes, size, w, h, codes))
        return TextureImage(w, h, std::move(codes), srgb);
    std::unique_ptr<unsigned char, void (*)(void*)> data(
        stbi_load_from_memory(bytes, length, &w, &h, &n, coverage ? 0 : 3), stbi_image_free);
    if (!data) throw std::runtime_error(stbi_failure_reason());
    return texture_of_codes(data.get(), w, h, coverage ? n : 3, srgb, coverage);
}

namespace {

/// An 8-bit image file (PNG, JPEG, WebP, TGA, BMP...) read whole, then decoded from memory.
TextureImage read_bytes(const fs::path& path, TexelMeaning meaning, size_t max_bytes) {
    const std::vector<unsigned char> bytes = read_input_file(path);
    return decode_texture(bytes.data(), bytes.size(), meaning, max_bytes);
}

TextureImage read_stb(const fs::path& path, TexelMeaning meaning, size_t max_bytes) {
    if (!stbi_is_hdr(path.c_str())) return read_bytes(path, meaning, max_bytes);
    int w = 0, h = 0, n = 0;
    if (!stbi_info(path.c_str(), &w, &h, &n)) throw std::runtime_error(stbi_failure_reason());
    check_texture_size(w, h, sizeof(Color), max_bytes);
    check_texels_per_byte(w, h, fs::file_size(path));
    std::unique_ptr<float, void (*)(void*)> data(stbi_loadf(path.c_str(), &w, &h, &n, 3),
                                                 stbi_image_free);
    if (!data) throw std::runtime_error(stbi_failure_reason());
    Image image(w, h);
    std::memcpy(image.pixels.data(), data.get(), image.pixels.size() * sizeof(Color));
    return TextureImage(std::move(image));
}

}  // namespace

TextureImage read_texture(const fs::path& path, bool srgb, size_t max_bytes,
                          const std::string& where, NegativeTexels negative) {
    return read_texture(path, srgb ? TexelMeaning::Srgb : TexelMeaning::Linear, max_bytes, where,
                        negative);
}

TextureImage read_texture(const fs::path& path, TexelMeaning meaning, size_t max_bytes,
                          const std::string& where, NegativeTexels negative) {
    std::string problem = input_file_problem(path);
    if (!problem.empty()) throw Error(path.string(), where, problem);
    TextureImage texture;
    try {
        std::string ext = lower_extension(path);
        texture = ext == ".pfm"   ? read_pfm(path, max_bytes)
                  : ext == ".exr" ? read_exr(path, max_bytes)
                                  : read_stb(path, meaning, max_bytes);
    } catch (const std::exception& e) {
        throw Error(path.string(), where, std::string("cannot read image: ") + e.what());
    }
    if (texture.is_8bit()) return texture;  // every code decodes to a colour in [0, 1]
    // Floating-point files may hold anything: a texel that is not a finite, non-negative
    // colour would reach the pixels as NaN or as negative light.
    for (int j = 0; j < texture.height(); ++j) {
        for (int i = 0; i < texture.width(); ++i) {
            Color c = texture.texel(i, j);
            if (is_finite(c) && c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f) continue;
            if (is_finite(c) && negative == NegativeTexels::ClampToZero) {
                texture.set_texel(i, j, glm::max(c, Color(0.0f)));
                continue;
            }
            char text[160];
            std::snprintf(text, sizeof text,
                          "texel (%d, %d) is (%g, %g, %g): an image must be finite and >= 0", i, j,
                          c.r, c.g, c.b);
            throw Error(path.string(), where, text);
        }
    }
    return texture;
}

}  // namespace svetlo
