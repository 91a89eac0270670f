#include "svetlo/core/crc32.h"

#ifdef SVETLO_HAS_ZLIB
#include <zlib.h>
#endif

namespace svetlo {

uint32_t crc32_plain(const unsigned char* data, size_t size) {
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t k = 0; k < size; ++k) {
        crc ^= data[k];
        for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return crc ^ 0xFFFFFFFFu;
}

uint32_t crc32_of(const unsigned char* data, size_t size) {
#ifdef SVETLO_HAS_ZLIB
    uLong crc = crc32(0L, Z_NULL, 0);
    // zlib takes at most 4 GiB a call.
    while (size > 0) {
        const auto part = static_cast<uInt>(size < 0x40000000u ? size : 0x40000000u);
        crc = crc32(crc, data, part);
        data += part;
        size -= part;
    }
    return static_cast<uint32_t>(crc);
#else
    return crc32_plain(data, size);
#endif
}

}  // namespace svetlo
