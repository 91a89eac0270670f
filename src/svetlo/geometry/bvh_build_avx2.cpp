// The BVH build's binning, partition and small spans' ranks with AVX2 (bvh_sah_sse.h's
// bin_range_avx2, partition_range_avx2 and rank_keys_avx2): used only where avx2_available(). The
// target is set by pragma after the headers, as in wide_bvh_avx2.cpp.
#include <immintrin.h>

#include "svetlo/geometry/bvh_sah_sse.h"

#pragma GCC push_options
#pragma GCC target("avx2,popcnt")  // every processor with AVX2 has POPCNT

namespace svetlo::sah::sse {

namespace {

/// Bins in eight-lane registers: lanes 0-2 the minimum, lanes 4-6 the maximum negated, so
/// that one minimum updates both. max(a, b) = -min(-a, -b) exactly, NaN and signed zeros
/// included (both instructions return their second operand then). Lanes 3 and 7 hold a
/// minimum of ids and bins, never read.
struct WideBins {
    __m256 box[kBins];
    uint32_t count[kBins];

    WideBins() {
        for (int b = 0; b < kBins; ++b) {
            box[b] = _mm256_set1_ps(kInfinity);
            count[b] = 0;
        }
    }

    /// Adds r, and notes its bin in it. Its bounds are loaded before the bin is stored (see
    /// bin_range).
    void add(BuildRef& r, const BinPosition& position) {
        const __m256 negate_max =
            _mm256_setr_ps(0.0f, 0.0f, 0.0f, 0.0f, -0.0f, -0.0f, -0.0f, -0.0f);
        const __m256 v = _mm256_xor_ps(_mm256_loadu_ps(&r.min.x), negate_max);
        const int b = position.bin(r);
        r.bin = static_cast<uint32_t>(b);
        box[b] = _mm256_min_ps(box[b], v);
        count[b]++;
    }
    void merge(const WideBins& o) {
        for (int b = 0; b < kBins; ++b) {
            box[b] = _mm256_min_ps(box[b], o.box[b]);
            count[b] += o.count[b];
        }
    }
    /// Adds these bins to `out`, the maximum negated back.
    void add_to(Bins& out) const {
        for (int b = 0; b < kBins; ++b) {
            out.min[b] = _mm_min_ps(out.min[b], _mm256_castps256_ps128(box[b]));
            out.max[b] = _mm_max_ps(
                out.max[b], _mm_xor_ps(_mm256_extractf128_ps(box[b], 1), _mm_set1_ps(-0.0f)));
            out.count[b] += count[b];
        }
    }
};

}  // namespace

void bin_range_avx2(BuildRef* refs, uint32_t first, uint32_t last, const BinPosition& position,
                    Bins& out) {
    WideBins even;
    uint32_t k = first;
    if (last - first >= 64) {  // two sets, as bin_range: one would chain every update on the last
        WideBins odd;
        for (; k + 1 < last; k += 2) {
            even.add(refs[k], position);
            odd.add(refs[k + 1], position);
        }
        even.merge(odd);
    }
    for (; k < last; ++k) even.add(refs[k], position);
    even.add_to(out);
}

void partition_range_avx2(const BuildRef* src, BuildRef* dst, uint32_t first, uint32_t last,
                          uint32_t next_left, uint32_t next_right, uint32_t last_left) {
    for (uint32_t j = first; j < last; ++j) {
        const __m256 r = _mm256_loadu_ps(&src[j].min.x);  // the whole reference
        const uint32_t right = src[j].bin > last_left ? 1u : 0u;
        _mm256_storeu_ps(&dst[next_left + ((next_right - next_left) & (0u - right))].min.x, r);
        next_left += 1u - right;
        next_right += right;
    }
}

void rank_keys_avx2(const float* key, uint32_t n, uint32_t* rank) {
    const int groups = static_cast<int>(n + 7) / 8;
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (uint32_t k = 0; k < n; ++k) {
        const __m256 own = _mm256_set1_ps(key[k]);
        const __m256i index = _mm256_set1_epi32(static_cast<int>(k));
        int below = 0;
        for (int g = 0; g < groups; ++g) {
            const __m256 other = _mm256_loadu_ps(key + 8 * g);
            const __m256i before =
                _mm256_cmpgt_epi32(index, _mm256_add_epi32(lanes, _mm256_set1_epi32(8 * g)));
            const __m256 lower = _mm256_or_ps(
                _mm256_cmp_ps(other, own, _CMP_LT_OQ),
                _mm256_and_ps(_mm256_cmp_ps(other, own, _CMP_EQ_OQ), _mm256_castsi256_ps(before)));
            below += _mm_popcnt_u32(static_cast<unsigned>(_mm256_movemask_ps(lower)));
        }
        rank[k] = static_cast<uint32_t>(below);
    }
}

}  // namespace svetlo::sah::sse

#pragma GCC pop_options
