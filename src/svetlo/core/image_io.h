// Reading and writing images. The format follows the file's extension:
//   .png  8-bit; colour is scaled by the exposure, clipped to [0, 1] and sRGB-encoded
//   .pfm  linear float RGB (header "PF", negative scale = little-endian, rows bottom to top)
//   .exr  linear float RGB (OpenEXR)
// Writes are atomic: the image goes to a temporary file beside the target, renamed over it
// only when complete, so a failed render never leaves a partial or damaged file.
#pragma once

#include <filesystem>
#include <string>

#include "svetlo/core/image.h"

namespace svetlo {

enum class ImageFormat { Png, Pfm, Exr };

/// What the pixels mean, which decides the 8-bit encoding: Radiance is scaled by the
/// exposure, clipped and sRGB-encoded; Data is a value already in [0, 1], written linearly
/// (visibility, normals mapped to [0, 1], normalised depth).
enum class PixelMeaning { Radiance, Data };

/// The format for a path's extension; throws Error(path, where, ...) for an unknown one.
ImageFormat image_format_for(const std::filesystem::path& path, const std::string& where);

/// Throws Error when a file cannot be created at `path` (missing folder, no permission),
/// without touching an existing file there. Call before a long render.
void check_writable(const std::filesystem::path& path, const std::string& where);

void write_image(const std::filesystem::path& path, const Image& image, PixelMeaning meaning,
                 float exposure, const std::string& where);

/// Reads PNG/JPEG/TGA/BMP (8-bit, sRGB-decoded unless `srgb` is false), HDR, PFM or EXR
/// (linear) into linear RGB with rows from the top. Throws Error(path, where, ...).
Image read_image(const std::filesystem::path& path, bool srgb, const std::string& where);

/// The largest image svetlo reads, in pixels (8192 x 8192: 768 MiB as float RGB), checked
/// from the file's header before anything is decoded.
inline constexpr long long kMaxImagePixels = 1LL << 26;

}  // namespace svetlo
