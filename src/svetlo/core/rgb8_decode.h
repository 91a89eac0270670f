// PNG and JPEG textures decoded by the fast libraries where the build has them: libspng (with
// zlib's inflate) and libjpeg-turbo. stb_image decodes everything else, and these two where a
// library is absent (the web) or refuses the file (texture_read.cpp).
#pragma once

#include <cstddef>
#include <vector>

namespace svetlo {

/// Decodes the PNG or JPEG in `bytes` into 8-bit RGB codes, row after row from the top, into
/// `codes`, for an image whose header says `width` x `height` texels (already checked against
/// the memory left for it). False, with `codes` untouched, when the bytes are neither format,
/// the library is not in this build, or it cannot decode them: the caller then asks stb, whose
/// message names the problem. 16-bit channels keep their high byte, grey is copied to R, G
/// and B, a palette is looked up; transparency and gAMA are ignored, as stb ignores them.
bool decode_rgb8(const unsigned char* bytes, size_t size, int width, int height,
                 std::vector<unsigned char>& codes);

/// Whether this build decodes PNG through libspng, and JPEG through libjpeg-turbo.
bool png_decoded_by_libspng();
bool jpeg_decoded_by_libjpeg();

}  // namespace svetlo
