// Stage 5: rasterization of the set-up triangles into a tile's buffers: Pineda's edge
// functions with the top-left rule (edge_function.h) and the depth test; passes with the
// stencil on or depth writes off go through rasterize_stencil.cpp.
//
// Three kernels here have an SSE form (four pixels of a row at once) and a plain twin
// (rasterize_kernels.h): rasterize_small, depth_test_four and deepest_of. The twins are the
// statement (read them first); the SSE forms, which an SVETLO_SIMD build uses, write the same
// depths, ids and barycentrics, bit for bit (tests/raster/kernel_twins_test.cpp).
#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <algorithm>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/raster/draw_pass.h"
#include "svetlo/raster/fragment.h"
#include "svetlo/raster/pipeline.h"
#include "svetlo/raster/rasterize_kernels.h"

namespace svetlo::raster {

namespace twin {

/// Stage 5 for small triangles at one sample per pixel (small_triangle.h), `e` at the span's
/// first sample and `z_origin` the depth there (depth_at): four pixels of a row tested and
/// depth-tested at once. Each written sample keeps its triangle `id` and screen barycentrics
/// (edge over twice the area, `inv_area`) for the shading (`kItems`; a depth-only pass keeps
/// the depth alone). The blocks' deepest depths are left as they were: larger than the truth,
/// which is safe. Both forms are inlined into draw_triangle below, once per small triangle
/// (the out-of-line copies are for the twins' test: called, the frame of a million small
/// triangles took 8 % longer).
template <bool kItems>
[[gnu::always_inline]] inline void rasterize_small(const SmallEdges& e, float z_origin,
                                                   const DepthPlane& p, PixelSpan span,
                                                   const Tile& tile, bool depth_test,
                                                   TileBuffers& buf, uint32_t id, float inv_area) {
    const auto [xs, xe, ys, ye] = span;
    const int tw = tile.x1 - tile.x0;
    for (int py = ys; py < ye; ++py) {
        const int row = py - ys;
        // The depth along the row, stepped as the SSE form's four lanes step it: lane L starts
        // at the row's depth plus L dzdx and moves 4 dzdx each four pixels.
        float z[4];
        for (int lane = 0; lane < 4; ++lane)
            z[lane] =
                (z_origin + p.dzdy * static_cast<float>(row)) + p.dzdx * static_cast<float>(lane);
        for (int px = xs; px < xe; px += 4) {
            for (int lane = 0; lane < 4 && px + lane < xe; ++lane) {
                const int32_t dx = px + lane - xs;
                int32_t w[3];  // E_k + bias_k: covered where all three are >= 0
                for (int k = 0; k < 3; ++k) w[k] = e.w[k] + dx * e.step_x[k] + row * e.step_y[k];
                if ((w[0] | w[1] | w[2]) < 0) continue;
                const size_t i = static_cast<size_t>(py - tile.y0) * tw + (px + lane - tile.x0);
                if (depth_test && !(z[lane] < buf.depth[i])) continue;
                buf.depth[i] = z[lane];
                if constexpr (kItems) {
                    // The barycentrics the shading reads back: E / (2 area), without the bias.
                    buf.tri[i] = id;
                    buf.l1[i] = static_cast<float>(w[1] - e.bias[1]) * inv_area;
                    buf.l2[i] = static_cast<float>(w[2] - e.bias[2]) * inv_area;
                }
            }
            for (float& zl : z) zl += 4.0f * p.dzdx;
        }
    }
}

template void rasterize_small<true>(const SmallEdges&, float, const DepthPlane&, PixelSpan,
                                    const Tile&, bool, TileBuffers&, uint32_t, float);
template void rasterize_small<false>(const SmallEdges&, float, const DepthPlane&, PixelSpan,
                                     const Tile&, bool, TileBuffers&, uint32_t, float);

}  // namespace twin

#if SVETLO_SIMD
namespace sse {

// rasterize_small's SSE form: its twin is above (twin::rasterize_small).
template <bool kItems>
[[gnu::always_inline]] inline void rasterize_small(const SmallEdges& e, float z_origin,
                                                   const DepthPlane& p, PixelSpan span,
                                                   const Tile& tile, bool depth_test,
                                                   TileBuffers& buf, uint32_t id, float inv_area) {
    const auto [xs, xe, ys, ye] = span;
    __m128i w_row[3], step_x[3], step_y[3];
    for (int k = 0; k < 3; ++k) {
        const int32_t a = e.step_x[k];
        w_row[k] = _mm_add_epi32(_mm_set1_epi32(e.w[k]), _mm_set_epi32(3 * a, 2 * a, a, 0));
        step_x[k] = _mm_set1_epi32(4 * a);
        step_y[k] = _mm_set1_epi32(e.step_y[k]);
    }
    // Depth: from the span's start, dzdy per row, dzdx per pixel, in float.
    const __m128 z_steps = _mm_mul_ps(_mm_set1_ps(p.dzdx), _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f));
    const __m128 z_step4 = _mm_set1_ps(4.0f * p.dzdx);
    const int tw = tile.x1 - tile.x0;
    const __m128i lane = _mm_set_epi32(3, 2, 1, 0);
    const __m128i id4 = _mm_set1_epi32(static_cast<int32_t>(id));
    // The barycentrics the shading reads back: E / (2 area), without the fill rule's bias.
    const __m128i bias1 = _mm_set1_epi32(e.bias[1]), bias2 = _mm_set1_epi32(e.bias[2]);
    const __m128 inv_area4 = _mm_set1_ps(inv_area);
    auto blend = [](__m128 mask, __m128 yes, __m128 no) {  // yes where mask, else no
        return _mm_or_ps(_mm_and_ps(mask, yes), _mm_andnot_ps(mask, no));
    };
    for (int py = ys; py < ye; ++py) {
        __m128i w0 = w_row[0], w1 = w_row[1], w2 = w_row[2];
        __m128 z4 =
            _mm_add_ps(_mm_set1_ps(z_origin + p.dzdy * static_cast<float>(py - ys)), z_steps);
        for (int px = xs; px < xe; px += 4) {
            // Covered (every edge function's sign bit clear) and within the span.
            __m128i outside = _mm_srai_epi32(_mm_or_si128(_mm_or_si128(w0, w1), w2), 31);
            __m128i in_span = _mm_cmplt_epi32(lane, _mm_set1_epi32(xe - px));
            __m128 covered = _mm_castsi128_ps(_mm_andnot_si128(outside, in_span));
            // Four samples at once, without a branch (whether any is covered is hard to
            // predict); the lanes not written write back what they read (the buffers have room
            // for four samples past the tile).
            size_t i = static_cast<size_t>(py - tile.y0) * tw + (px - tile.x0);
            __m128 old_z = _mm_loadu_ps(&buf.depth[i]);
            __m128 pass = depth_test ? _mm_and_ps(covered, _mm_cmplt_ps(z4, old_z)) : covered;
            _mm_storeu_ps(&buf.depth[i], blend(pass, z4, old_z));
            if constexpr (kItems) {
                __m128i old_id = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&buf.tri[i]));
                __m128i pass_i = _mm_castps_si128(pass);
                _mm_storeu_si128(
                    reinterpret_cast<__m128i*>(&buf.tri[i]),
                    _mm_or_si128(_mm_and_si128(pass_i, id4), _mm_andnot_si128(pass_i, old_id)));
                __m128 l1 = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(w1, bias1)), inv_area4);
                __m128 l2 = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(w2, bias2)), inv_area4);
                _mm_storeu_ps(&buf.l1[i], blend(pass, l1, _mm_loadu_ps(&buf.l1[i])));
                _mm_storeu_ps(&buf.l2[i], blend(pass, l2, _mm_loadu_ps(&buf.l2[i])));
            }
            w0 = _mm_add_epi32(w0, step_x[0]);
            w1 = _mm_add_epi32(w1, step_x[1]);
            w2 = _mm_add_epi32(w2, step_x[2]);
            z4 = _mm_add_ps(z4, z_step4);
        }
        for (int k = 0; k < 3; ++k) w_row[k] = _mm_add_epi32(w_row[k], step_y[k]);
    }
}

template void rasterize_small<true>(const SmallEdges&, float, const DepthPlane&, PixelSpan,
                                    const Tile&, bool, TileBuffers&, uint32_t, float);
template void rasterize_small<false>(const SmallEdges&, float, const DepthPlane&, PixelSpan,
                                     const Tile&, bool, TileBuffers&, uint32_t, float);

}  // namespace sse
#endif

namespace {

/// Stage 5: rasterizes triangle `id` into the tile's visibility buffer, 8 x 8 blocks at a
/// time: a block where the triangle's nearest depth lies behind everything stored is skipped.
/// Depth is the plane z(x, y) of the depth keys, stepped incrementally along each row.
void rasterize(uint32_t id, const SetupTriangle& t, const TriangleEdges& te, PixelSpan span,
               const Tile& tile, const SamplePattern& sp, bool depth_test, TileBuffers& buf) {
    const auto [xs, xe, ys, ye] = span;
    const Edge& e0 = te.e[0];
    const Edge& e1 = te.e[1];
    const Edge& e2 = te.e[2];
    auto px_per_fixed = static_cast<double>(kSubpixel);
    double dzdx, dzdy;
    te.depth_gradient(t, dzdx, dzdy);
    float zmin = std::min({t.z[0], t.z[1], t.z[2]});
    const int tw = tile.x1 - tile.x0, S = sp.count, kB = TileBuffers::kBlock, bw = kTile / kB;
    const int64_t d0 = e0.a * kSubpixel, d1 = e1.a * kSubpixel, d2 = e2.a * kSubpixel;
    for (int by = (ys - tile.y0) / kB; by <= (ye - 1 - tile.y0) / kB; ++by) {
        for (int bx = (xs - tile.x0) / kB; bx <= (xe - 1 - tile.x0) / kB; ++bx) {
            float& far = buf.block_far[static_cast<size_t>(by) * bw + bx];
            if (depth_test && zmin >= far) continue;  // hidden in the whole block
            int x0 = std::max(xs, tile.x0 + bx * kB), x1 = std::min(xe, tile.x0 + (bx + 1) * kB);
            int y0 = std::max(ys, tile.y0 + by * kB), y1 = std::min(ye, tile.y0 + (by + 1) * kB);
            bool wrote = false;
            // A block whose every sample is inside all three edges (the edge functions are
            // linear: checking the corners suffices) needs only the depth test, four pixels
            // at a time.
            bool full = S == 1;
            for (int k = 0; k < 3 && full; ++k) {
                const Edge& e = te.e[k];
                int64_t xa = static_cast<int64_t>(x0) * kSubpixel,
                        xb = static_cast<int64_t>(x1) * kSubpixel - 1;
                int64_t ya = static_cast<int64_t>(y0) * kSubpixel,
                        yb = static_cast<int64_t>(y1) * kSubpixel - 1;
                int64_t lowest = std::min(std::min(e.at(xa, ya), e.at(xb, ya)),
                                          std::min(e.at(xa, yb), e.at(xb, yb)));
                full = lowest + e.bias >= 0;
            }
            if (full) {
                auto dz = static_cast<float>(dzdx);
                for (int py = y0; py < y1; ++py) {
                    double fx = static_cast<double>(static_cast<int64_t>(x0) * kSubpixel +
                                                    sp.ox[0] - t.x[0]) /
                                px_per_fixed;
                    double fy = static_cast<double>(static_cast<int64_t>(py) * kSubpixel +
                                                    sp.oy[0] - t.y[0]) /
                                px_per_fixed;
                    auto z = static_cast<float>(t.z[0] + dzdx * fx + dzdy * fy);
                    size_t i = static_cast<size_t>(py - tile.y0) * tw + (x0 - tile.x0);
                    int px = x0;
                    for (; px + 4 <= x1; px += 4, i += 4, z += 4.0f * dz)
                        wrote |= kernel::depth_test_four(z, dz, i, id, depth_test, buf);
                    for (; px < x1; ++px, ++i, z += dz) {
                        if (depth_test && !(z < buf.depth[i])) continue;
                        buf.depth[i] = z;
                        buf.tri[i] = id;
                        wrote = true;
                    }
                }
            }
            for (int py = y0; py < y1 && !full; ++py) {
                for (int s = 0; s < S; ++s) {
                    int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[s];
                    int64_t sx = static_cast<int64_t>(x0) * kSubpixel + sp.ox[s];
                    int64_t w0 = e0.at(sx, sy) + e0.bias, w1 = e1.at(sx, sy) + e1.bias,
                            w2 = e2.at(sx, sy) + e2.bias;
                    double fx = static_cast<double>(sx - t.x[0]) / px_per_fixed,
                           fy = static_cast<double>(sy - t.y[0]) / px_per_fixed;
                    auto z = static_cast<float>(t.z[0] + dzdx * fx + dzdy * fy);
                    auto dz = static_cast<float>(dzdx);
                    size_t i = (static_cast<size_t>(py - tile.y0) * tw + (x0 - tile.x0)) * S + s;
                    for (int px = x0; px < x1;
                         ++px, w0 += d0, w1 += d1, w2 += d2, z += dz, i += S) {
                        if ((w0 | w1 | w2) < 0) continue;
                        if (depth_test && !(z < buf.depth[i])) continue;
                        buf.depth[i] = z;
                        buf.tri[i] = id;
                        wrote = true;
                    }
                }
            }
            if (wrote && depth_test) {
                // The block's deepest sample may have come nearer: the max over its rows (each
                // row of the block is contiguous).
                float deepest = -kInfinity;
                int px0 = bx * kB, px1 = std::min(tw, (bx + 1) * kB);
                for (int py = tile.y0 + by * kB; py < std::min(tile.y1, tile.y0 + (by + 1) * kB);
                     ++py) {
                    const float* row =
                        buf.depth.data() + (static_cast<size_t>(py - tile.y0) * tw + px0) * S;
                    deepest = kernel::deepest_of(row, static_cast<size_t>(px1 - px0) * S, deepest);
                }
                far = deepest;
            }
        }
    }
}

/// Stage 5 for a triangle with alpha (alpha_test.h), sample by sample: covered, nearer, and
/// not a hole at its perspective-correct texture coordinates. The blocks' deepest depths are
/// left as they were (larger than the truth: safe).
void rasterize_alpha(uint32_t id, const SetupTriangle& t, const PassGeometry& f, PixelSpan span,
                     const Tile& tile, const SamplePattern& sp, const PipelineState& state,
                     TileBuffers& buf) {
    const TriangleEdges te(t);
    double dzdx, dzdy;
    te.depth_gradient(t, dzdx, dzdy);
    const int tw = tile.x1 - tile.x0, S = sp.count;
    for (int py = span.ys; py < span.ye; ++py) {
        for (int px = span.xs; px < span.xe; ++px) {
            for (int s = 0; s < S; ++s) {
                const int64_t sx = static_cast<int64_t>(px) * kSubpixel + sp.ox[s];
                const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[s];
                const int64_t w0 = te.e[0].at(sx, sy) + te.e[0].bias,
                              w1 = te.e[1].at(sx, sy) + te.e[1].bias,
                              w2 = te.e[2].at(sx, sy) + te.e[2].bias;
                if ((w0 | w1 | w2) < 0) continue;
                const auto z = static_cast<float>(
                    t.z[0] + dzdx * static_cast<double>(sx - t.x[0]) / kSubpixel +
                    dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel);
                const size_t i = (static_cast<size_t>(py - tile.y0) * tw + (px - tile.x0)) * S + s;
                if (state.depth_test && !(z < buf.depth[i])) continue;
                if (in_alpha_hole(f, id, t, te, sx, sy, state)) continue;
                buf.depth[i] = z;
                buf.tri[i] = id;
            }
        }
    }
}

/// Stage 5 for one triangle in one tile, depth written: the small-triangle path or the
/// general one (or, for a triangle with alpha, rasterize_alpha).
void draw_triangle(uint32_t id, const SetupTriangle& t, const PassGeometry& f, const Tile& tile,
                   const SamplePattern& sp, const PipelineState& state, TileBuffers& buf) {
    const PixelSpan span = span_in(t, tile);
    if (span.empty()) return;
    if (state.alpha && state.alpha->active(t.material)) {
        rasterize_alpha(id, t, f, span, tile, sp, state, buf);
        return;
    }
    if (t.small && sp.count == 1) {
        // Relative to the span's first sample.
        const int32_t sx = span.xs * kSubpixel + sp.ox[0], sy = span.ys * kSubpixel + sp.oy[0];
        const int32_t rx[3] = {t.x[0] - sx, t.x[1] - sx, t.x[2] - sx},
                      ry[3] = {t.y[0] - sy, t.y[1] - sy, t.y[2] - sy};
        const SmallEdges e = small_edges(rx, ry);
        const DepthPlane p = depth_plane(rx, ry, t.z, t.inv_area);
        const float z_origin = depth_at(p, -rx[0], -ry[0]);
        if (state.write_items) {
            kernel::rasterize_small<true>(e, z_origin, p, span, tile, state.depth_test, buf, id,
                                          t.inv_area);
        } else {
            kernel::rasterize_small<false>(e, z_origin, p, span, tile, state.depth_test, buf);
        }
    } else {
        rasterize(id, t, TriangleEdges(t), span, tile, sp, state.depth_test, buf);
    }
}

}  // namespace

bool in_alpha_hole(const PassGeometry& f, uint32_t id, const SetupTriangle& t,
                   const TriangleEdges& te, int64_t sx, int64_t sy, const PipelineState& state) {
    const ClipVertex& A = f.vertex(t.v[0]);
    const ClipVertex& B = f.vertex(t.v[1]);
    const ClipVertex& C = f.vertex(t.v[2]);
    const Weights w = perspective_weights(te.weights(sx, sy), A, B, C);
    const Varyings at = varyings_at(A, B, C, w.b);
    // The triangle as the item buffer numbers it (PipelineState::items): the same coin in
    // every pass that draws it, whatever list holds it.
    const uint32_t source = f.source(id);
    const uint32_t item = state.items ? state.items[source] : state.first_item + source;
    const uint64_t key =
        (static_cast<uint64_t>(sy) << 40) ^ (static_cast<uint64_t>(sx) << 20) ^ item;
    return state.alpha->hole(t.material, at, key);
}

SamplePattern sample_pattern(int spp, uint64_t seed, int first, int count) {
    SamplePattern p;
    p.count = count;
    for (int s = 0; s < count; ++s) {
        int k = first + s;
        vec2 o(0.5f);
        if (spp > 1) {
            Rng rng(seed * 0x9e3779b97f4a7c15ULL + static_cast<uint64_t>(k), 0x5ca1ab1eULL);
            o = stratified_sample(k, spp, rng.next_2d());
        }
        p.ox[s] = std::min(kSubpixel - 1, static_cast<int32_t>(o.x * kSubpixel));
        p.oy[s] = std::min(kSubpixel - 1, static_cast<int32_t>(o.y * kSubpixel));
        p.offset[s] = vec2(static_cast<float>(p.ox[s]), static_cast<float>(p.oy[s])) /
                      static_cast<float>(kSubpixel);
    }
    return p;
}

void rasterize_tile(const PassGeometry& f, const Tile& tile, const SamplePattern& sp,
                    const PipelineState& state, TileBuffers& buf) {
    if (state.stencil.enabled || !state.depth_write) {
        rasterize_tile_stencil(f, tile, sp, state, buf);
        return;
    }
    for_each_binned(f, tile, [&](uint32_t id, const SetupTriangle& t) {
        draw_triangle(id, t, f, tile, sp, state, buf);
    });
#if SVETLO_SIMD
    if (f.depth_records()) rasterize_depth_avx2(f, tile, buf);
#endif
}

}  // namespace svetlo::raster
