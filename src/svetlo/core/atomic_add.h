// Adding to a plain integer from many threads at once (std::atomic_ref's fetch_add, C++20),
// as the compilers' builtin: the browser's libc++ (emscripten 3.1.6, libc++ 13) does not have
// std::atomic_ref yet.
#pragma once

#include <cstdint>

namespace svetlo {

/// x += v atomically, with no ordering of other memory (a counter or a sum read after a join).
inline void atomic_add_relaxed(uint64_t& x, uint64_t v) {
    __atomic_fetch_add(&x, v, __ATOMIC_RELAXED);
}

}  // namespace svetlo
