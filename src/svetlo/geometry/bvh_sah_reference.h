// The binned SAH's pieces in plain C++ (Wald, "On fast Construction of SAH-based Bounding
// Volume Hierarchies", IEEE RT 2007): the statement of what bvh_sah_sse.h computes with SSE,
// and the kernels themselves where svetlo is built without SIMD (SVETLO_SIMD=OFF, ARM64).
// Each piece gives the SSE form's results (tests/geometry/bvh_sah_test.cpp): the same counts,
// ranks and split, bounds equal as numbers. The SSE binning meets the references in another
// order (two interleaved sets of bins), so of two equal zeros a bin may keep the other sign,
// and a NaN coordinate may be kept where the other form drops it.
#pragma once

#include <span>

#include "svetlo/geometry/bvh_sah.h"
#include "svetlo/geometry/geometry.h"

namespace svetlo::sah::reference {

/// The minimum and maximum as SSE's minps and maxps define them, per coordinate: a where
/// a < b (a > b), else b, so a NaN in either gives b. Called with the SSE form's operands in
/// its order.
inline vec3 box_min(vec3 a, vec3 b) { return glm::min(b, a); }
inline vec3 box_max(vec3 a, vec3 b) { return glm::max(b, a); }

/// SAH bins: the bounds of the references whose centroid falls in each, and their count.
struct Bins {
    vec3 min[kBins], max[kBins];
    uint32_t count[kBins];
    Bins() {
        for (int b = 0; b < kBins; ++b) {
            min[b] = vec3(kInfinity);
            max[b] = vec3(-kInfinity);
            count[b] = 0;
        }
    }
    void add(int b, const BuildRef& r) {
        min[b] = box_min(min[b], r.min);
        max[b] = box_max(max[b], r.max);
        count[b]++;
    }
    void merge(const Bins& o) {
        for (int b = 0; b < kBins; ++b) {
            min[b] = box_min(min[b], o.min[b]);
            max[b] = box_max(max[b], o.max[b]);
            count[b] += o.count[b];
        }
    }
};

/// Adds refs[first, last) to `out` along `position`'s axis, and notes each reference's bin in
/// it for the partition. (No AVX2 form: `avx2` is there for the SSE form's signature.)
inline void bin_range(BuildRef* refs, uint32_t first, uint32_t last, const BinPosition& position,
                      Bins& out, bool /*avx2*/ = false) {
    for (uint32_t k = first; k < last; ++k) {
        const int b = position.bin(refs[k]);
        refs[k].bin = static_cast<uint32_t>(b);
        out.add(b, refs[k]);
    }
}

/// Copies src[first, last) into dst in order: the references binned at most `last_left` to the
/// slots from next_left on, the others to the slots from next_right on.
inline void partition_range(const BuildRef* src, BuildRef* dst, uint32_t first, uint32_t last,
                            uint32_t next_left, uint32_t next_right, uint32_t last_left,
                            bool /*avx2*/ = false) {
    for (uint32_t j = first; j < last; ++j) {
        if (src[j].bin <= last_left) {
            dst[next_left++] = src[j];
        } else {
            dst[next_right++] = src[j];
        }
    }
}

/// The rank of each of n keys (none NaN): how many keys are smaller, plus how many equal ones
/// come before it (a stable sort's position).
inline void rank_keys(const float* key, uint32_t n, uint32_t* rank, bool /*avx2*/ = false) {
    for (uint32_t k = 0; k < n; ++k) {
        uint32_t below = 0;
        for (uint32_t j = 0; j < n; ++j) below += key[j] < key[k] || (key[j] == key[k] && j < k);
        rank[k] = below;
    }
}

/// A cell of a sweep: a bin, or one reference.
struct Cell {
    vec3 min, max;
    uint32_t count;
};
inline Cell cell_of(const BuildRef& r) { return Cell{r.min, r.max, 1}; }
inline void copy_ref(const BuildRef& from, BuildRef& to) { to = from; }
inline Bounds3 to_bounds(vec3 lo, vec3 hi) { return Bounds3{lo, hi}; }

/// The cells' bounds from the left (cells 0..b) and from the right (cells b.. on), and the SAH
/// cost of splitting after each cell, area × count on each side.
struct Sweep {
    vec3 left_min[kBins], left_max[kBins];
    vec3 right_min[kBins + 1], right_max[kBins + 1];  // past the last cell: the empty box
    int left_count[kBins];                            // references in cells 0..b
    uint32_t n;
    int cells;

    /// `cell_of(b)` gives cell b of `cells` (at most kBins), which hold `total` references.
    template <class CellOf>
    Sweep(int cell_count, uint32_t total, const CellOf& cell_of) : n(total), cells(cell_count) {
        vec3 lo(kInfinity), hi(-kInfinity);
        int count = 0;
        for (int b = 0; b < cells; ++b) {
            const Cell cell = cell_of(b);
            left_min[b] = lo = box_min(lo, cell.min);
            left_max[b] = hi = box_max(hi, cell.max);
            left_count[b] = count += static_cast<int>(cell.count);
        }
        lo = vec3(kInfinity);
        hi = vec3(-kInfinity);
        right_min[cells] = lo;
        right_max[cells] = hi;
        for (int b = cells - 1; b >= 0; --b) {
            const Cell cell = cell_of(b);
            right_min[b] = lo = box_min(lo, cell.min);
            right_max[b] = hi = box_max(hi, cell.max);
        }
    }

    /// A box's surface area, 2 (x y + y z + z x).
    static float area(vec3 lo, vec3 hi) {
        const vec3 e = hi - lo;
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }

    /// The cheapest split (the first of equal costs) and its cost, or -1 when no split leaves
    /// references on both sides with a finite cost below best_cost.
    int cheapest(float& best_cost) const {
        int best = -1;
        float least = kInfinity;
        for (int b = 0; b + 1 < cells; ++b) {  // split after cell b
            const int left = left_count[b], right = static_cast<int>(n) - left;
            if (left <= 0 || right <= 0) continue;
            const float cost = area(left_min[b], left_max[b]) * static_cast<float>(left) +
                               area(right_min[b + 1], right_max[b + 1]) * static_cast<float>(right);
            if (cost < least) {
                least = cost;
                best = b;
            }
        }
        if (best < 0 || !(least < best_cost)) return -1;
        best_cost = least;
        return best;
    }
};

/// The references [first, last) (the triangles, then the bounded shapes) written into refs,
/// and their bounds and centroid bounds.
inline void make_refs(const Geometry& geometry, std::span<const uint32_t> shapes, size_t first,
                      size_t last, BuildRef* refs, Bounds3& bounds, Bounds3& centroids) {
    const size_t triangles = geometry.triangle_count();
    vec3 b_min(kInfinity), b_max(-kInfinity), c_min(kInfinity), c_max(-kInfinity);
    for (size_t k = first; k < last; ++k) {
        BuildRef& r = refs[k];
        if (k < triangles) {
            const vec3 a = geometry.positions[geometry.indices[3 * k]],
                       v1 = geometry.positions[geometry.indices[3 * k + 1]],
                       v2 = geometry.positions[geometry.indices[3 * k + 2]];
            r.min = box_min(box_min(v2, v1), a);
            r.max = box_max(box_max(v2, v1), a);
            r.id = static_cast<uint32_t>(k);
        } else {
            r.id = shapes[k - triangles];
            const Bounds3 pb = geometry.primitive_bounds(r.id);
            r.min = pb.min;
            r.max = pb.max;
        }
        r.bin = 0;
        b_min = box_min(r.min, b_min);
        b_max = box_max(r.max, b_max);
        c_min = box_min(r.centroid(), c_min);
        c_max = box_max(r.centroid(), c_max);
    }
    bounds = Bounds3{b_min, b_max};
    centroids = Bounds3{c_min, c_max};
}

}  // namespace svetlo::sah::reference
