// std::bit_cast (C++20) as the compilers' builtin: the browser's libc++ (emscripten 3.1.6,
// libc++ 13) does not have it yet.
#pragma once

namespace svetlo {

/// The bits of `from` read as a `To` of the same size.
template <class To, class From>
constexpr To bit_cast(const From& from) noexcept {
    static_assert(sizeof(To) == sizeof(From));
    return __builtin_bit_cast(To, from);
}

}  // namespace svetlo
