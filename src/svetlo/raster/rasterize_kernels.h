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

namespace twin {  // rasterize.cpp

/// A small triangle at one sample per pixel over `span`: coverage by its edge functions `e`
/// (at the span's first sample), the depth from `z_origin` stepped along the rows, the depth
/// test, and with kItems the triangle's id and screen barycentrics.
template <bool kItems>
void rasterize_small(const SmallEdges& e, float z_origin, const DepthPlane& p, PixelSpan span,
                     const Tile& tile, bool depth_test, TileBuffers& buf, uint32_t id = 0,
                     float inv_area = 0.0f);
/// Four samples from i on, wholly inside a triangle, at depths z + dz lane: depth-tested and
/// written with `id`. Whether any was written.
bool depth_test_four(float z, float dz, size_t i, uint32_t id, bool depth_test, TileBuffers& buf);
/// The deepest of n depths from `row` on, and `deepest`.
float deepest_of(const float* row, size_t n, float deepest);
/// Widens [near, far] to hold the n depths from z on (draw_pass.cpp: a block's depth range
/// for the hierarchical test of a pass that writes no depth). Here, to be inlined there.
inline void depth_range(const float* z, size_t n, float& near, float& far) {
    for (size_t k = 0; k < n; ++k) {
        near = std::min(near, z[k]);
        far = std::max(far, z[k]);
    }
}

}  // namespace twin

#if SVETLO_SIMD
namespace sse {  // rasterize.cpp: the twins' SSE forms

template <bool kItems>
void rasterize_small(const SmallEdges& e, float z_origin, const DepthPlane& p, PixelSpan span,
                     const Tile& tile, bool depth_test, TileBuffers& buf, uint32_t id = 0,
                     float inv_area = 0.0f);
bool depth_test_four(float z, float dz, size_t i, uint32_t id, bool depth_test, TileBuffers& buf);
float deepest_of(const float* row, size_t n, float deepest);

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
