// What kind of image a file holds, from its first bytes (each format's own signature).
#pragma once

#include <cstddef>
#include <cstring>

namespace svetlo {

/// PNG: the 8-byte signature of PNG (Third Edition), 5.2.
inline bool is_png(const unsigned char* bytes, size_t size) {
    static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    return size >= 8 && std::memcmp(bytes, kSignature, 8) == 0;
}

/// JPEG: the SOI marker and the first marker after it (ITU T.81, B.1.1.3).
inline bool is_jpeg(const unsigned char* bytes, size_t size) {
    return size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
}

/// WebP: a RIFF file whose form is WEBP.
inline bool is_webp(const unsigned char* bytes, size_t size) {
    return size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 &&
           std::memcmp(bytes + 8, "WEBP", 4) == 0;
}

/// The first bytes one of the signatures above needs.
inline constexpr size_t kImageSignatureBytes = 12;

}  // namespace svetlo
