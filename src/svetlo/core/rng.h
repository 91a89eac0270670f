// Deterministic random numbers. Every pixel owns a stream keyed by (seed, pixel index), so
// an image does not depend on the number of threads or the order in which tiles run.
#pragma once

#include <cstdint>

#include "svetlo/core/math.h"

namespace svetlo {

/// PCG32 (O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
/// Algorithms for Random Number Generation", 2014): 64-bit state, 32-bit output.
class Rng {
public:
    Rng(uint64_t seed, uint64_t stream) {
        inc_ = (stream << 1u) | 1u;
        state_ = 0;
        next_u32();
        state_ += seed;
        next_u32();
    }

    uint32_t next_u32() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        auto rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }

    /// Uniform in [0, 1): the top 24 bits, so the result is never rounded up to 1.
    float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
    /// Two in a row, x first.
    vec2 next_2d() {
        float x = next_float();
        float y = next_float();
        return {x, y};
    }

private:
    uint64_t state_;
    uint64_t inc_;
};

/// A well-mixed 64-bit hash (SplitMix64 finaliser), to turn (seed, pixel) into a stream key.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

inline Rng pixel_rng(uint64_t seed, uint64_t pixel_index) {
    return Rng(mix64(seed), mix64(pixel_index ^ mix64(seed + 1)));
}

}  // namespace svetlo
