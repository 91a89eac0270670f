// Numbers read from bytes in memory at any alignment (a file's buffers), in the machine's
// byte order.
#pragma once

#include <cstring>

namespace svetlo {

/// The T stored at p (not necessarily aligned for T).
template <class T>
T load_bytes(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

}  // namespace svetlo
