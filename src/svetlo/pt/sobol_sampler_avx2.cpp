// SobolSampler::next_8 with AVX2 (sobol_sampler.h): four pairs of dimensions in eight 32-bit
// lanes, lane L holding dimension d + L of pair L / 2 (sobol_shuffled, then sobol_dimension).
// Every step is the scalar code's operation lane by lane (32-bit multiplications wrap alike), so
// the numbers are the same. The target is set by pragma after the headers, as in the rasterizer's
// AVX2 files.
#include <immintrin.h>

#include "svetlo/pt/sobol_sampler.h"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace svetlo {

namespace {

__m256i mul(__m256i x, uint32_t c) {
    return _mm256_mullo_epi32(x, _mm256_set1_epi32(static_cast<int>(c)));
}
__m256i xor_shift_right(__m256i x, int s) { return _mm256_xor_si256(x, _mm256_srli_epi32(x, s)); }

/// sobol_hash, lane by lane.
__m256i hash8(__m256i key, __m256i salt) {
    __m256i x = _mm256_xor_si256(key, mul(salt, 0x9e3779b9u));
    x = mul(xor_shift_right(x, 16), 0x7feb352du);
    x = mul(xor_shift_right(x, 15), 0x846ca68bu);
    return xor_shift_right(x, 16);
}

/// reverse_bits: the bytes of each lane swapped, then each byte's nibbles looked up reversed.
__m256i reverse8(__m256i x) {
    const __m256i bswap = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3,
                                           2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
    // A nibble reversed, in the low and in the high half of a byte.
    const __m256i low = _mm256_setr_epi8(0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd,
                                         0x3, 0xb, 0x7, 0xf, 0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe,
                                         0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf);
    const __m256i high = _mm256_slli_epi16(low, 4);  // no byte exceeds 0x0f: nothing crosses
    const __m256i nibble = _mm256_set1_epi8(0x0f);
    x = _mm256_shuffle_epi8(x, bswap);
    __m256i lo = _mm256_and_si256(x, nibble);
    __m256i hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), nibble);
    return _mm256_or_si256(_mm256_shuffle_epi8(high, lo), _mm256_shuffle_epi8(low, hi));
}

/// owen_of_reversed, lane by lane.
__m256i owen8(__m256i r, __m256i seed) {
    __m256i x = _mm256_add_epi32(r, seed);
    x = _mm256_xor_si256(x, mul(x, 0x6c50b47cu));
    x = _mm256_xor_si256(x, mul(x, 0xb82f1e52u));
    x = _mm256_xor_si256(x, mul(x, 0xc7afe638u));
    x = _mm256_xor_si256(x, mul(x, 0x8d22f6e6u));
    return reverse8(x);
}

/// One step of sobol1_reversed: the bits under `mask` take in those s places above them.
__m256i superset_step(__m256i v, int s, uint32_t mask) {
    __m256i m = _mm256_set1_epi32(static_cast<int>(mask));
    return _mm256_xor_si256(v, _mm256_and_si256(_mm256_srli_epi32(v, s), m));
}

/// sobol1_reversed, lane by lane.
__m256i sobol1_8(__m256i i) {
    i = superset_step(i, 1, 0x55555555u);
    i = superset_step(i, 2, 0x33333333u);
    i = superset_step(i, 4, 0x0f0f0f0fu);
    i = superset_step(i, 8, 0x00ff00ffu);
    return xor_shift_right(i, 16);
}

}  // namespace

void sobol_draw8_avx2(uint32_t key, uint32_t reversed_index, uint32_t d, float* out) {
    const __m256i keys = _mm256_set1_epi32(static_cast<int>(key));
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i dim = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(d)), lane);
    // Pair k = dim / 2 in both of its lanes: the shuffled index (salt 2k + 1).
    const __m256i pair_salt = _mm256_or_si256(dim, _mm256_set1_epi32(1));
    const __m256i index =
        owen8(_mm256_set1_epi32(static_cast<int>(reversed_index)), hash8(keys, pair_salt));
    // Even lanes: the first Sobol dimension (the index itself, reversed), odd: the second.
    const __m256i point = _mm256_blend_epi32(index, sobol1_8(index), 0b10101010);
    const __m256i scrambled = owen8(point, hash8(keys, _mm256_add_epi32(dim, dim)));
    // sobol_to_unit: the top 24 bits, exactly representable, times 2^-24.
    const __m256 unit = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(scrambled, 8)),
                                      _mm256_set1_ps(0x1p-24f));
    _mm256_storeu_ps(out, unit);
}

}  // namespace svetlo

#pragma GCC pop_options
