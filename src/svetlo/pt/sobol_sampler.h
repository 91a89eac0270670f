// The path tracer's sample values: Owen-scrambled Sobol points, padded pair by pair (Burley,
// "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020). Sample index i of a pixel is its
// pass. Dimensions are used in order; each pair of dimensions (2k, 2k+1) takes the first two
// Sobol dimensions, a (0, 2)-sequence in base 2, at an index shuffled by a nested uniform
// scramble seeded by (pixel, k), and each coordinate is Owen-scrambled with a seed of its own.
// The passes of a pixel are then stratified in every pair of dimensions, and the pairs are
// independent of one another: a path tracer's error falls faster at low sample counts than
// with independent random numbers, at the same cost.
//
// A path vertex draws its eight dimensions at once (next_8): where the processor has AVX2,
// the four pairs' hashes, scrambles and bit reversals run in eight lanes
// (sobol_sampler_avx2.cpp), with the same numbers as the scalar code.
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

/// The second Sobol dimension at index i, bit-reversed (as the Owen scramble takes it). Its
/// primitive polynomial is x + 1: bit k of the index contributes the direction number v_k,
/// v_0 = 2^31, v_(k+1) = v_k ^ (v_k >> 1), whose bit 31 - j is the binomial C(k, j) mod 2,
/// that is 1 when the bits of j are among those of k (Lucas). So bit j of the reversed point
/// is the parity of the index's bits k that hold j's bits: a superset sum over the five-bit
/// positions, one shift, mask and xor per position bit.
constexpr uint32_t sobol1_reversed(uint32_t i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    return i ^ (i >> 16);
}

/// Laine and Karras' hash, which permutes the bits as an Owen scramble does, from the lowest
/// up (Burley 2020, listing 2, with Burley's improved constants).
constexpr uint32_t laine_karras(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/// The Owen scramble of the fixed-point number in [0, 1) whose bits, reversed, are r:
/// reverse_bits(laine_karras(reverse_bits(x), seed)) for x = reverse_bits(r). Every number
/// here is kept reversed until scrambled, so each costs one reversal, not two.
constexpr uint32_t owen_of_reversed(uint32_t r, uint32_t seed) {
    return reverse_bits(laine_karras(r, seed));
}

/// A 32-bit hash of a pixel's key and `salt` (Wellons' lowbias32 finaliser).
constexpr uint32_t sobol_hash(uint32_t key, uint32_t salt) {
    uint32_t x = key ^ (salt * 0x9e3779b9u);
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    return x ^ (x >> 16);
}

/// A fixed-point number's top 24 bits as a float in [0, 1).
constexpr float sobol_to_unit(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }

/// The shuffled index of pair k of the sample whose index, bit-reversed, is reversed_index:
/// the index under a nested uniform scramble (an Owen scramble of the index), salt 2k + 1.
constexpr uint32_t sobol_shuffled(uint32_t key, uint32_t reversed_index, uint32_t k) {
    return owen_of_reversed(reversed_index, sobol_hash(key, 2 * k + 1));
}

/// Dimension d at its pair's shuffled index i: the first Sobol dimension for an even d, the
/// second for an odd one, Owen-scrambled with salt 2d.
constexpr float sobol_dimension(uint32_t key, uint32_t i, uint32_t d) {
    return sobol_to_unit(owen_of_reversed(d & 1u ? sobol1_reversed(i) : i, sobol_hash(key, 2 * d)));
}

/// Dimensions d to d + 7 (d even) of the sample whose index, bit-reversed, is
/// reversed_index, under the pixel's key: four next_2d() in eight AVX2 lanes. Call only
/// where avx2_available() (geometry/avx2.h).
void sobol_draw8_avx2(uint32_t key, uint32_t reversed_index, uint32_t d, float* out);

class SobolSampler {
public:
    /// The sampler of `pixel`'s sample `index` under `seed`; `avx2` lets next_8 use AVX2 (pass
    /// avx2_available()).
    SobolSampler(uint64_t seed, uint64_t pixel, uint32_t index, bool avx2 = false)
        : key_(static_cast<uint32_t>(mix64(mix64(seed ^ 0x50b01ULL) + pixel))),
          reversed_index_(reverse_bits(index)),
          avx2_(avx2) {}

    /// The next dimension.
    float next_float() {
        const uint32_t d = dimension_++;
        if (d >> 1 != pair_) {  // the pair's shuffled index, kept for its second dimension
            pair_ = d >> 1;
            pair_index_ = shuffled(pair_);
        }
        return sobol_dimension(key_, pair_index_, d);
    }
    /// The next pair of dimensions, starting at an even one: stratified together.
    vec2 next_2d() {
        const uint32_t d = dimension_ + (dimension_ & 1u);
        dimension_ = d + 2;
        return pair(d);
    }
    /// The next four pairs of dimensions, as four next_2d() would draw them.
    std::array<vec2, 4> next_8() {
        const uint32_t d = dimension_ + (dimension_ & 1u);
        dimension_ = d + 8;
        std::array<vec2, 4> out;
        if (avx2_) {
            sobol_draw8_avx2(key_, reversed_index_, d, &out[0].x);
        } else {
            for (uint32_t k = 0; k < 4; ++k) out[k] = pair(d + 2 * k);
        }
        return out;
    }

private:
    /// Dimensions d and d + 1 (d even).
    vec2 pair(uint32_t d) const {
        const uint32_t i = shuffled(d >> 1);
        return {sobol_dimension(key_, i, d), sobol_dimension(key_, i, d + 1)};
    }
    uint32_t shuffled(uint32_t k) const { return sobol_shuffled(key_, reversed_index_, k); }

    uint32_t key_;
    uint32_t reversed_index_;  // the sample's index, bit-reversed
    bool avx2_;
    uint32_t dimension_ = 0;
    uint32_t pair_ = ~0u, pair_index_ = 0;  // next_float's last pair and its shuffled index
};

}  // namespace svetlo
