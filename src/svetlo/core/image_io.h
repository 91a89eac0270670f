// Reading and writing images. The format follows the file's extension:
//   .png  8-bit; colour is scaled by the exposure, clipped to [0, 1] and sRGB-encoded
//   .pfm  linear float RGB (header "PF", negative scale = little-endian, rows bottom to top)
//   .exr  linear float RGB (OpenEXR)
// Writes are atomic: the image goes to a temporary file beside the target, renamed over it
// only when complete, so a failed render never leaves a partial or damaged file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/core/texture_image.h"

namespace svetlo {

enum class ImageFormat { Png, Pfm, Exr };

/// What the pixels mean, which decides the 8-bit encoding: Radiance is scaled by the
/// exposure, clipped and sRGB-encoded; Data is a value already in [0, 1], written linearly
/// (visibility, normals mapped to [0, 1], normalised depth).
enum class PixelMeaning { Radiance, Data };

/// True when the path's extension is one svetlo writes (.png, .pfm, .exr, any case).
bool is_image_path(const std::filesystem::path& path);

/// The format for a path's extension; throws Error(path, where, ...) for an unknown one.
ImageFormat image_format_for(const std::filesystem::path& path, const std::string& where);

/// Throws Error when a file cannot be created at `path` (missing folder, no permission),
/// without touching an existing file there. Call before a long render.
void check_writable(const std::filesystem::path& path, const std::string& where);
/// The same for a file of any kind (a page, a JSON file), without the image format's check.
void check_creatable(const std::filesystem::path& path, const std::string& where);

/// The key under which an image carries svetlo's metadata (its provenance): a PNG iTXt
/// chunk's keyword, an EXR header's string attribute; a PFM has it in `OUT.pfm.json`.
inline constexpr const char* kMetadataKey = "svetlo";

/// Writes `image` atomically; `metadata` (text, usually JSON), when not empty, goes inside
/// the file or, for PFM, into the sidecar `path.json`, written before the image is renamed
/// into place.
void write_image(const std::filesystem::path& path, const Image& image, PixelMeaning meaning,
                 float exposure, const std::string& where, const std::string& metadata = {});

/// The bytes of `image` as a PNG file (as write_image writes it): for pages that inline it.
std::vector<unsigned char> encode_png(const Image& image, PixelMeaning meaning, float exposure,
                                      const std::string& metadata = {});

/// The bytes of an image as a JPEG of `quality` (1-100), its pixels made as a PNG's are
/// (radiance: exposure, clipping, sRGB; data: clipping): fast and lossy, for the viewer while
/// the view moves.
std::vector<unsigned char> encode_jpeg(const Image& image, PixelMeaning meaning, float exposure,
                                       int quality);

/// The metadata that write_image stored with the image, empty when there is none.
std::string read_image_metadata(const std::filesystem::path& path, const std::string& where);

/// An image read whole as linear RGB: an 8-bit PNG decoded through the sRGB curve (`ldr`
/// true), PFM and EXR as they are. Throws Error(path, where, ...).
struct LoadedImage {
    Image image;
    bool ldr = false;
};
LoadedImage read_image(const std::filesystem::path& path, const std::string& where);

/// The largest image read_image reads: 8192² float pixels (the largest film).
inline constexpr size_t kMaxFilmImageBytes = size_t{8192} * 8192 * 12;

/// Reads a texture: PNG, JPEG, TGA and BMP keep their 8-bit codes (decoded through the sRGB
/// curve unless `srgb` is false; 16-bit files are read at 8 bits), HDR, PFM and EXR float
/// RGB. A texture whose texels would take more than `max_bytes` in memory is refused from
/// the file's header, before anything is decoded; so is one past 65536 texels a side. Texels
/// that are not finite, non-negative colours are refused, naming the texel. Throws
/// Error(path, where, ...).
/// A file's extension in lower case, with its dot (".exr"), which says its format.
std::string lower_extension(const std::filesystem::path& path);

/// What read_texture makes of a finite texel below zero: refuse it, or (environment maps,
/// whose lossy EXR compressions, DWAA, DWAB and B44, leave small negative values) make it 0.
enum class NegativeTexels { Refuse, ClampToZero };
TextureImage read_texture(const std::filesystem::path& path, bool srgb, size_t max_bytes,
                          const std::string& where,
                          NegativeTexels negative = NegativeTexels::Refuse);
/// What an image's texels mean: a colour (sRGB or linear), or coverage (alpha), read from its
/// alpha channel where it has one (grey-alpha, RGBA) and from its first channel otherwise,
/// into all three channels. Float files (PFM, EXR, HDR) give their red channel as coverage.
enum class TexelMeaning { Srgb, Linear, Coverage };
TextureImage read_texture(const std::filesystem::path& path, TexelMeaning meaning, size_t max_bytes,
                          const std::string& where,
                          NegativeTexels negative = NegativeTexels::Refuse);
/// stb's decoded 8-bit texels (`n` channels each) as coverage texels (TexelMeaning::Coverage).
std::vector<unsigned char> coverage_codes(const unsigned char* data, int n, size_t texels);
/// An 8-bit image held in memory (PNG, JPEG, BMP, TGA, GIF by stb; WebP by libwebp where the
/// build has it, reads_webp()) as `meaning` says, its size checked from its header first
/// (at most `max_bytes` of texels). Throws std::runtime_error saying why it does not decode.
TextureImage decode_texture(const unsigned char* bytes, size_t size, TexelMeaning meaning,
                            size_t max_bytes);
/// Whether this build reads WebP (libwebp, Debian's libwebp-dev).
bool reads_webp();
/// Whether this build reads OpenEXR files (not in the browser's: docs/web.md).
bool reads_exr();

/// The most memory one texture's texels may take: a 16384² 8-bit texture (3 bytes a texel)
/// or an 8192² float one (12 bytes a texel). The rasterizer's mipmaps add a third.
inline constexpr size_t kMaxTextureBytes = size_t{768} << 20;
/// The most memory all of a scene's textures may take together.
inline constexpr size_t kMaxSceneTextureBytes = size_t{2048} << 20;

}  // namespace svetlo
