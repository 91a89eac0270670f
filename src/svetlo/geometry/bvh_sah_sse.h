// The binned SAH's bins, binning, partition, ranks and sweep with SSE (four lanes; the
// binning, partition and ranks also with AVX2: bvh_build_avx2.cpp). Their twins, the plain
// statement of each, are in bvh_sah_reference.h; the results are the same (bounds equal as
// numbers, counts, ranks and the chosen split exactly: tests/geometry/bvh_sah_test.cpp).
#pragma once

#include <immintrin.h>

#include <span>

#include "svetlo/geometry/bvh_sah.h"
#include "svetlo/geometry/geometry.h"

namespace svetlo::sah::sse {

/// SAH bins: the bounds (SSE registers; lane 3 unused) and the count of each.
struct Bins {
    __m128 min[kBins], max[kBins];
    uint32_t count[kBins];
    Bins() {
        for (int b = 0; b < kBins; ++b) {
            min[b] = _mm_set1_ps(kInfinity);
            max[b] = _mm_set1_ps(-kInfinity);
            count[b] = 0;
        }
    }
    /// Adds a reference's bounds, loaded whole (lane 3 holds its id or bin, never read back).
    void add(int b, __m128 lo, __m128 hi) {
        min[b] = _mm_min_ps(min[b], lo);
        max[b] = _mm_max_ps(max[b], hi);
        count[b]++;
    }
    void merge(const Bins& o) {
        for (int b = 0; b < kBins; ++b) {
            min[b] = _mm_min_ps(min[b], o.min[b]);
            max[b] = _mm_max_ps(max[b], o.max[b]);
            count[b] += o.count[b];
        }
    }
};

/// Adds refs[first, last) to `out` along `position`'s axis and notes each reference's bin in
/// it, as bin_range below, with AVX2 (bvh_build_avx2.cpp): call it only where
/// avx2_available() (avx2.h). The same bins, bit for bit.
void bin_range_avx2(BuildRef* refs, uint32_t first, uint32_t last, const BinPosition& position,
                    Bins& out);

/// Adds refs[first, last) to `out` along `position`'s axis, and notes each reference's bin in
/// it for the partition. Long ranges go through two interleaved sets of bins: consecutive
/// primitives of a mesh often fall into the same bin, and one set would chain every update on
/// the previous one; for a short one, the second set costs more to clear and merge than it
/// saves. With `avx2`, every range takes bin_range_avx2 (one update per reference instead of
/// two: 5 % of the build).
inline void bin_range(BuildRef* refs, uint32_t first, uint32_t last, const BinPosition& position,
                      Bins& out, bool avx2) {
    if (avx2) {
        bin_range_avx2(refs, first, last, position, out);
        return;
    }
    // The bounds are loaded before the bin is stored: a load over a store still in flight
    // that it only partly covers waits for the store to land.
    auto add = [&](BuildRef& r, Bins& bins) {
        const __m128 lo = _mm_loadu_ps(&r.min.x), hi = _mm_loadu_ps(&r.max.x);
        const int b = position.bin(r);
        r.bin = static_cast<uint32_t>(b);
        bins.add(b, lo, hi);
    };
    uint32_t k = first;
    if (last - first >= 64) {
        Bins second;
        for (; k + 1 < last; k += 2) {
            add(refs[k], out);
            add(refs[k + 1], second);
        }
        out.merge(second);
    }
    for (; k < last; ++k) add(refs[k], out);
}

/// partition_range with AVX2 (bvh_build_avx2.cpp): call it only where avx2_available().
void partition_range_avx2(const BuildRef* src, BuildRef* dst, uint32_t first, uint32_t last,
                          uint32_t next_left, uint32_t next_right, uint32_t last_left);

/// Copies src[first, last) into dst in order, the references binned at most `last_left` to the
/// slots from next_left on and the others to the slots from next_right on. The slot is chosen
/// with a mask: written as a conditional, the compiler makes it a branch, which mispredicts
/// half the time. With `avx2`, partition_range_avx2 (one 32-byte copy per reference instead
/// of two 16-byte ones: 2 % of the build).
inline void partition_range(const BuildRef* src, BuildRef* dst, uint32_t first, uint32_t last,
                            uint32_t next_left, uint32_t next_right, uint32_t last_left,
                            bool avx2) {
    if (avx2) {
        partition_range_avx2(src, dst, first, last, next_left, next_right, last_left);
        return;
    }
    for (uint32_t j = first; j < last; ++j) {
        const uint32_t right = src[j].bin > last_left ? 1u : 0u;
        dst[next_left + ((next_right - next_left) & (0u - right))] = src[j];
        next_left += 1u - right;
        next_right += right;
    }
}

/// rank_keys with AVX2 (bvh_build_avx2.cpp): call it only where avx2_available().
void rank_keys_avx2(const float* key, uint32_t n, uint32_t* rank);

/// The rank of each of n <= kBins keys (none NaN; kBins of them, padded with +inf, 16-byte
/// aligned): the keys below it, and the equal ones before it, a stable order. Every
/// key is compared with four at a time (eight with `avx2`) without a branch: the insertion
/// sort's exits mispredicted.
inline void rank_keys(const float* key, uint32_t n, uint32_t* rank, bool avx2) {
    if (avx2) {
        rank_keys_avx2(key, n, rank);
        return;
    }
    const int groups = static_cast<int>(n + 3) / 4;
    for (uint32_t k = 0; k < n; ++k) {
        const __m128 own = _mm_set1_ps(key[k]);
        const __m128i index = _mm_set1_epi32(static_cast<int>(k));
        __m128i below = _mm_setzero_si128();
        for (int g = 0; g < groups; ++g) {
            const __m128 other = _mm_load_ps(key + 4 * g);
            const __m128i before =
                _mm_cmpgt_epi32(index, _mm_setr_epi32(4 * g, 4 * g + 1, 4 * g + 2, 4 * g + 3));
            const __m128 lower =
                _mm_or_ps(_mm_cmplt_ps(other, own),
                          _mm_and_ps(_mm_cmpeq_ps(other, own), _mm_castsi128_ps(before)));
            below = _mm_sub_epi32(below, _mm_castps_si128(lower));  // a true lane is -1
        }
        below = _mm_add_epi32(below, _mm_shuffle_epi32(below, _MM_SHUFFLE(1, 0, 3, 2)));
        below = _mm_add_epi32(below, _mm_shuffle_epi32(below, _MM_SHUFFLE(2, 3, 0, 1)));
        rank[k] = static_cast<uint32_t>(_mm_cvtsi128_si32(below));
    }
}

/// A cell of a sweep: a bin, or one reference.
struct Cell {
    __m128 min, max;
    uint32_t count;
};

/// The cells' bounds from the left (cells 0..b) and from the right (cells b.. on), and the SAH
/// cost of splitting after each cell: area × count on each side, four splits at a time. The
/// cells are the bins of a large span, or the references of a small one sorted along the axis.
struct Sweep {
    __m128 left_min[kBins], left_max[kBins];
    __m128 right_min[kBins + 1], right_max[kBins + 1];  // past the last cell: the empty box
    alignas(16) int left_count[kBins];                  // references in cells 0..b
    uint32_t n;
    int groups;  // of four splits

    /// `cell_of(b)` gives cell b of `cells` (at most kBins), which hold `total` references.
    template <class CellOf>
    Sweep(int cells, uint32_t total, const CellOf& cell_of) : n(total), groups((cells + 3) / 4) {
        __m128 lo = _mm_set1_ps(kInfinity), hi = _mm_set1_ps(-kInfinity);
        int count = 0;
        for (int b = 0; b < cells; ++b) {
            const Cell cell = cell_of(b);
            left_min[b] = lo = _mm_min_ps(lo, cell.min);
            left_max[b] = hi = _mm_max_ps(hi, cell.max);
            left_count[b] = count += static_cast<int>(cell.count);
        }
        // Splits past the last cell, up to the end of its group: nothing on the right.
        for (int b = cells; b < 4 * groups; ++b) {
            left_min[b] = lo;
            left_max[b] = hi;
            left_count[b] = count;
        }
        lo = _mm_set1_ps(kInfinity);
        hi = _mm_set1_ps(-kInfinity);
        for (int b = cells; b <= 4 * groups; ++b) {
            right_min[b] = lo;
            right_max[b] = hi;
        }
        for (int b = cells - 1; b >= 0; --b) {
            const Cell cell = cell_of(b);
            right_min[b] = lo = _mm_min_ps(lo, cell.min);
            right_max[b] = hi = _mm_max_ps(hi, cell.max);
        }
    }

    /// The surface areas of four boxes, 2 (x y + y z + z x) in lanes, the same operations in
    /// the same order as one box at a time.
    static __m128 areas(const __m128* lo, const __m128* hi) {
        __m128 x = _mm_sub_ps(hi[0], lo[0]), y = _mm_sub_ps(hi[1], lo[1]);
        __m128 z = _mm_sub_ps(hi[2], lo[2]), w = _mm_sub_ps(hi[3], lo[3]);
        _MM_TRANSPOSE4_PS(x, y, z, w);
        __m128 sum = _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, y), _mm_mul_ps(y, z)), _mm_mul_ps(z, x));
        return _mm_mul_ps(_mm_set1_ps(2.0f), sum);
    }

    /// The cheapest split (the first of equal costs) and its cost, or -1 when no split leaves
    /// references on both sides with a finite cost. Found without a branch per split: the
    /// least cost of all lanes, then the first lane that holds it (a scan with a comparison
    /// per split mispredicted a few times per node, a fifth of a small node's time).
    int cheapest(float& best_cost) const {
        __m128 cost[kBins / 4];
        __m128 least = _mm_set1_ps(kInfinity);
        const __m128i total = _mm_set1_epi32(static_cast<int>(n));
        for (int g = 0; g < groups; ++g) {
            const int b = 4 * g;
            // Split after cell b + lane: the left side is cells 0..b + lane, the right side the
            // cells from b + lane + 1 on (none past the last cell: masked below).
            __m128 right_area = areas(right_min + b + 1, right_max + b + 1);
            __m128i left = _mm_load_si128(reinterpret_cast<const __m128i*>(left_count + b));
            __m128i right = _mm_sub_epi32(total, left);
            __m128 c =
                _mm_add_ps(_mm_mul_ps(areas(left_min + b, left_max + b), _mm_cvtepi32_ps(left)),
                           _mm_mul_ps(right_area, _mm_cvtepi32_ps(right)));
            // Both sides must hold references (counts are below 2^31, so signed compares).
            __m128i both = _mm_and_si128(_mm_cmpgt_epi32(left, _mm_setzero_si128()),
                                         _mm_cmpgt_epi32(right, _mm_setzero_si128()));
            __m128 valid =
                _mm_and_ps(_mm_castsi128_ps(both), _mm_cmplt_ps(c, _mm_set1_ps(kInfinity)));
            cost[g] = _mm_or_ps(_mm_and_ps(valid, c), _mm_andnot_ps(valid, _mm_set1_ps(kInfinity)));
            least = _mm_min_ps(least, cost[g]);
        }
        least = _mm_min_ps(least, _mm_shuffle_ps(least, least, _MM_SHUFFLE(1, 0, 3, 2)));
        least = _mm_min_ps(least, _mm_shuffle_ps(least, least, _MM_SHUFFLE(2, 3, 0, 1)));
        const float lowest = _mm_cvtss_f32(least);
        if (!(lowest < best_cost)) return -1;  // every cost infinite (invalid)
        int mask = 0;
        for (int g = groups - 1; g >= 0; --g)
            mask = (mask << 4) | _mm_movemask_ps(_mm_cmpeq_ps(cost[g], least));
        best_cost = lowest;
        return __builtin_ctz(static_cast<unsigned>(mask));
    }
};

/// A reference as a sweep's cell, and a reference copied whole. Loaded whole before it is
/// stored: copied as a struct, its second half was read after the first half's store, whose
/// address the load had to wait for.
inline Cell cell_of(const BuildRef& r) {
    return Cell{_mm_loadu_ps(&r.min.x), _mm_loadu_ps(&r.max.x), 1};
}
inline void copy_ref(const BuildRef& from, BuildRef& to) {
    const __m128 lo = _mm_loadu_ps(&from.min.x), hi = _mm_loadu_ps(&from.max.x);
    _mm_storeu_ps(&to.min.x, lo);
    _mm_storeu_ps(&to.max.x, hi);
}

/// Bounds from two SSE registers (lane 3 ignored).
inline Bounds3 to_bounds(__m128 lo, __m128 hi) {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    return Bounds3{vec3(l[0], l[1], l[2]), vec3(h[0], h[1], h[2])};
}

/// A vertex in an SSE register (lane 3 zero), read as 8 + 4 bytes: 16 would pass the end of
/// the array at its last vertex.
inline __m128 load_vertex(const vec3& v) {
    return _mm_movelh_ps(_mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(&v.x)),
                         _mm_load_ss(&v.z));
}

/// The references [first, last) (the triangles, then the bounded shapes) written into refs,
/// and their bounds and centroid bounds. _mm_min_ps(b, a) is glm::min(a, b), NaN included.
inline void make_refs(const Geometry& geometry, std::span<const uint32_t> shapes, size_t first,
                      size_t last, BuildRef* refs, Bounds3& bounds, Bounds3& centroids) {
    const size_t triangles = geometry.triangle_count();
    const vec3* p = geometry.positions.data();
    const uint32_t* index = geometry.indices.data();
    const __m128 half = _mm_set1_ps(0.5f);
    __m128 b_min = _mm_set1_ps(kInfinity), b_max = _mm_set1_ps(-kInfinity);
    __m128 c_min = b_min, c_max = b_max;
    for (size_t k = first; k < last; ++k) {
        __m128 lo, hi;
        uint32_t id;
        if (k < triangles) {  // the common case, three vertices
            id = static_cast<uint32_t>(k);
            // The vertices of the triangle kAhead on are asked for now: a mesh's triangles
            // reach for vertices all over its array, and the loads waited on the memory.
            constexpr size_t kAhead = 16;
            if (k + kAhead < triangles) {
                for (int j = 0; j < 3; ++j) __builtin_prefetch(&p[index[3 * (k + kAhead) + j]]);
            }
            const __m128 a = load_vertex(p[index[3 * k]]), v1 = load_vertex(p[index[3 * k + 1]]),
                         v2 = load_vertex(p[index[3 * k + 2]]);
            lo = _mm_min_ps(_mm_min_ps(v2, v1), a);
            hi = _mm_max_ps(_mm_max_ps(v2, v1), a);
        } else {
            id = shapes[k - triangles];
            const Bounds3 pb = geometry.primitive_bounds(id);
            lo = _mm_setr_ps(pb.min.x, pb.min.y, pb.min.z, 0.0f);
            hi = _mm_setr_ps(pb.max.x, pb.max.y, pb.max.z, 0.0f);
        }
        BuildRef& r = refs[k];
        _mm_storeu_ps(&r.min.x, lo);
        _mm_storeu_ps(&r.max.x, hi);
        r.id = id;
        r.bin = 0;
        b_min = _mm_min_ps(lo, b_min);
        b_max = _mm_max_ps(hi, b_max);
        const __m128 c = _mm_add_ps(_mm_mul_ps(half, lo), _mm_mul_ps(half, hi));  // centroid()
        c_min = _mm_min_ps(c, c_min);
        c_max = _mm_max_ps(c, c_max);
    }
    bounds = to_bounds(b_min, b_max);
    centroids = to_bounds(c_min, c_max);
}

}  // namespace svetlo::sah::sse
