// CRC-32 (ISO 3309, the PNG chunks' check, PNG spec 5.5): zlib's where it is built, the plain
// bitwise statement elsewhere (the browser's WebAssembly); the tests hold the two equal.
#pragma once

#include <cstddef>
#include <cstdint>

namespace svetlo {

/// The CRC-32 of `size` bytes at `data`.
uint32_t crc32_of(const unsigned char* data, size_t size);

/// The same, computed bit by bit (the reflected polynomial 0xEDB88320).
uint32_t crc32_plain(const unsigned char* data, size_t size);

}  // namespace svetlo
