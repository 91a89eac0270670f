// The rasterizer's SIMD kernels and their scalar twins (docs/kernels.md), each in two forms of
// one signature: `twin::` states the algorithm (read it), `sse::` computes the same bits four
// samples at a time. An SVETLO_SIMD build draws with the SSE forms, a scalar build with the
// twins, and tests/raster/kernel_twins_test.cpp runs both on the same inputs.
#pragma once

#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "svetlo/raster/pipeline.h"
#include "svetlo/raster/small_triangle.h"

namespace svetlo::raster {

// depth_test_four, deepest_of and depth_range run in the inner loops of their callers, a few
// samples a call: they are defined here, to be inlined there (out of line, in rasterize.cpp,
// depth_test_four alone was 7 % of the profile of `svetlo_raster_bench 1 9 fragment`).
namespace twin {  // rasterize_small: rasterize.cpp

/// A small triangle at one sample per pixel over `span`: coverage by its edge functions `e`
/// (at the span's first sample), the depth from `z_origin` stepped along the rows, the depth
/// test, and with kItems the triangle's id and screen barycentrics.
template <bool kItems>
void rasterize_small(const SmallEdges& e, float z_origin, const DepthPlane& p, PixelSpan span,
                     const Tile& tile, bool depth_test, TileBuffers& buf, uint32_t id = 0,
                     float inv_area = 0.0f);
/// Four pixels of a block's row wholly inside the triangle, from sample i on, at depths
/// z + dz lane: depth-tested (with `depth_test`) and written. Whether any was written.
inline bool depth_test_four(float z, float dz, size_t i, uint32_t id, bool depth_test,
                            TileBuffers& buf) {
    bool wrote = false;
    for (int lane = 0; lane < 4; ++lane) {
        const float zl = z + dz * static_cast<float>(lane);
        if (depth_test && !(zl < buf.depth[i + lane])) continue;
        buf.depth[i + lane] = zl;
        buf.tri[i + lane] = id;
        wrote = true;
    }
    return wrote;
}

/// The deepest of n depths from `row` on, and `deepest`.
inline float deepest_of(const float* row, size_t n, float deepest) {
    for (size_t i = 0; i < n; ++i) deepest = std::max(deepest, row[i]);
    return deepest;
}
/// Widens [near, far] to hold the n depths from z on (draw_pass.cpp: a block's depth range
/// for the hierarchical test of a pass that writes no depth).
inline void depth_range(const float* z, size_t n, float& near, float& far) {
    for (size_t k = 0; k < n; ++k) {
        near = std::min(near, z[k]);
        far = std::max(far, z[k]);
    }
}

}  // namespace twin

#if SVETLO_SIMD
namespace sse {  // the twins' SSE forms (rasterize_small: rasterize.cpp)

template <bool kItems>
void rasterize_small(const SmallEdges& e, float z_origin, const DepthPlane& p, PixelSpan span,
                     const Tile& tile, bool depth_test, TileBuffers& buf, uint32_t id = 0,
                     float inv_area = 0.0f);

/// twin::depth_test_four's SSE form.
inline bool depth_test_four(float z, float dz, size_t i, uint32_t id, bool depth_test,
                            TileBuffers& buf) {
    const __m128 steps = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f);
    __m128 z4 = _mm_add_ps(_mm_set1_ps(z), _mm_mul_ps(_mm_set1_ps(dz), steps));
    __m128 d = _mm_loadu_ps(&buf.depth[i]);
    __m128 m = depth_test ? _mm_cmplt_ps(z4, d) : _mm_castsi128_ps(_mm_set1_epi32(-1));
    if (_mm_movemask_ps(m) == 0) return false;
    _mm_storeu_ps(&buf.depth[i], _mm_or_ps(_mm_and_ps(m, z4), _mm_andnot_ps(m, d)));
    auto* tp = reinterpret_cast<__m128i*>(&buf.tri[i]);
    __m128i mi = _mm_castps_si128(m);
    const __m128i ids = _mm_set1_epi32(static_cast<int>(id));
    _mm_storeu_si128(
        tp, _mm_or_si128(_mm_and_si128(mi, ids), _mm_andnot_si128(mi, _mm_loadu_si128(tp))));
    return true;
}

/// twin::deepest_of's SSE form: the max four lanes at a time.
inline float deepest_of(const float* row, size_t n, float deepest) {
    __m128 lanes4 = _mm_set1_ps(deepest);
    size_t i = 0;
    for (; i + 4 <= n; i += 4) lanes4 = _mm_max_ps(lanes4, _mm_loadu_ps(row + i));
    for (; i < n; ++i) deepest = std::max(deepest, row[i]);
    alignas(16) float lanes[4];
    _mm_store_ps(lanes, lanes4);
    return std::max({lanes[0], lanes[1], lanes[2], lanes[3], deepest});
}

/// twin::depth_range four lanes at a time, then the rest (min and max are exact in any order).
inline void depth_range(const float* z, size_t n, float& near, float& far) {
    __m128 lo = _mm_set1_ps(near), hi = _mm_set1_ps(far);
    size_t k = 0;
    for (; k + 4 <= n; k += 4) {
        lo = _mm_min_ps(lo, _mm_loadu_ps(z + k));
        hi = _mm_max_ps(hi, _mm_loadu_ps(z + k));
    }
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    near = std::min({l[0], l[1], l[2], l[3]});
    far = std::max({h[0], h[1], h[2], h[3]});
    for (; k < n; ++k) {
        near = std::min(near, z[k]);
        far = std::max(far, z[k]);
    }
}

}  // namespace sse
#endif

/// The forms this build draws with: the SSE forms where it has them, else the twins.
#if SVETLO_SIMD
namespace kernel = sse;
#else
namespace kernel = twin;
#endif

}  // namespace svetlo::raster
