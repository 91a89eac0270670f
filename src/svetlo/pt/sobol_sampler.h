// The path tracer's sample values: Owen-scrambled Sobol points, padded pair by pair (Burley,
// "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020). Sample index i of a pixel is its
// pass. Dimensions are used in order; each pair of dimensions (2k, 2k+1) takes the first two
// Sobol dimensions, a (0, 2)-sequence in base 2, at an index shuffled by a nested uniform
// scramble seeded by (pixel, k), and each coordinate is Owen-scrambled with a seed of its own.
// The passes of a pixel are then stratified in every pair of dimensions, and the pairs are
// independent of one another: a path tracer's error falls faster at low sample counts than
// with independent random numbers, at the same cost.
#pragma once

#include <array>
#include <cstdint>

#include "svetlo/core/math.h"
#include "svetlo/core/rng.h"

namespace svetlo {

/// The bits of x in reverse order: a byte swap, then the bits of each byte.
constexpr uint32_t reverse_bits(uint32_t x) {
    x = (x << 24) | ((x & 0xff00u) << 8) | ((x >> 8) & 0xff00u) | (x >> 24);  // bswap
    x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
    x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
    return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

/// The second Sobol dimension (primitive polynomial x + 1) is linear over GF(2) in the index's
/// bits: bit k contributes the direction number v_k, v_0 = 2^31, v_{k+1} = v_k ^ (v_k >> 1).
/// Tabulated per byte of the index (at compile time), so a point costs four lookups; the
/// tables hold the numbers bit-reversed, as the Owen scramble takes them (reversing is linear
/// over GF(2) too).
using SobolByteTables = std::array<std::array<uint32_t, 256>, 4>;
constexpr SobolByteTables sobol_byte_tables_reversed() {
    SobolByteTables t{};
    uint32_t v[32] = {};
    v[0] = 1u << 31;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    for (int byte = 0; byte < 4; ++byte) {
        for (uint32_t x = 0; x < 256; ++x) {
            uint32_t r = 0;
            for (int b = 0; b < 8; ++b) {
                if (x & (1u << b)) r ^= v[8 * byte + b];
            }
            t[static_cast<size_t>(byte)][x] = reverse_bits(r);
        }
    }
    return t;
}
inline constexpr SobolByteTables kSobolTablesReversed = sobol_byte_tables_reversed();

class SobolSampler {
public:
    /// The sampler of `pixel`'s sample `index` under `seed`.
    SobolSampler(uint64_t seed, uint64_t pixel, uint32_t index)
        : key_(static_cast<uint32_t>(mix64(mix64(seed ^ 0x50b01ULL) + pixel))),
          reversed_index_(reverse_bits(index)) {}

    /// The next dimension.
    float next_float() {
        const uint32_t d = dimension_++;
        if (d >> 1 != pair_) {  // the pair's shuffled index, kept for its second dimension
            pair_ = d >> 1;
            pair_index_ = shuffled(pair_);
        }
        const uint32_t i = pair_index_;
        return to_unit(d & 1u ? owen_of_reversed(sobol1_reversed(i), seed(d))
                              : owen_of_reversed(i, seed(d)));
    }
    /// The next pair of dimensions, starting at an even one: stratified together.
    vec2 next_2d() {
        const uint32_t d = dimension_ + (dimension_ & 1u);
        dimension_ = d + 2;
        const uint32_t i = shuffled(d >> 1);
        return {to_unit(owen_of_reversed(i, seed(d))),
                to_unit(owen_of_reversed(sobol1_reversed(i), seed(d + 1)))};
    }

private:
    static float to_unit(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }

    /// Laine and Karras' hash, which permutes the bits as an Owen scramble does, from the
    /// lowest up (Burley 2020, listing 2, with Burley's improved constants).
    static uint32_t laine_karras(uint32_t x, uint32_t seed) {
        x += seed;
        x ^= x * 0x6c50b47cu;
        x ^= x * 0xb82f1e52u;
        x ^= x * 0xc7afe638u;
        x ^= x * 0x8d22f6e6u;
        return x;
    }
    /// The Owen scramble of the fixed-point number in [0, 1) whose bits, reversed, are r:
    /// reverse_bits(laine_karras(reverse_bits(x), seed)) for x = reverse_bits(r). Every
    /// number here is kept reversed until scrambled, so each costs one reversal, not two.
    static uint32_t owen_of_reversed(uint32_t r, uint32_t seed) {
        return reverse_bits(laine_karras(r, seed));
    }
    /// The second Sobol dimension at index i, bit-reversed.
    static uint32_t sobol1_reversed(uint32_t i) {
        const auto& t = kSobolTablesReversed;
        return t[0][i & 0xffu] ^ t[1][(i >> 8) & 0xffu] ^ t[2][(i >> 16) & 0xffu] ^ t[3][i >> 24];
    }
    /// A 32-bit hash of the pixel's key and `salt` (Wellons' lowbias32 finaliser).
    uint32_t hash(uint32_t salt) const {
        uint32_t x = key_ ^ (salt * 0x9e3779b9u);
        x ^= x >> 16;
        x *= 0x7feb352du;
        x ^= x >> 15;
        x *= 0x846ca68bu;
        return x ^ (x >> 16);
    }
    /// The scramble of dimension d, and the shuffled index of pair k: the sample's index
    /// under a nested uniform scramble (an Owen scramble of the index).
    uint32_t seed(uint32_t d) const { return hash(2 * d); }
    uint32_t shuffled(uint32_t k) const {
        return owen_of_reversed(reversed_index_, hash(2 * k + 1));
    }

    uint32_t key_;
    uint32_t reversed_index_;  // the sample's index, bit-reversed
    uint32_t dimension_ = 0;
    uint32_t pair_ = ~0u, pair_index_ = 0;  // next_float's last pair and its shuffled index
};

}  // namespace svetlo
