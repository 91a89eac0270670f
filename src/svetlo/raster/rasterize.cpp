// Stage 5: rasterization of the set-up triangles into a tile's buffers: Pineda's edge
// functions with the top-left rule (edge_function.h), the stencil test (stencil.h) and the
// depth test.
#include <immintrin.h>

#include <algorithm>
#include <cstring>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

namespace {

/// Stage 5 for small triangles and one sample per pixel: edge functions relative to the
/// triangle's corner fit in 32 bits, so four pixels are tested and depth-tested at once, and
/// each written sample keeps its triangle and screen barycentrics for the shading (`kItems`;
/// a depth-only pass keeps the depth alone). The blocks' deepest depths are left as they
/// were: larger than the truth, which is safe.
template <bool kItems>
void rasterize_small(uint32_t id, const SetupTriangle& t, PixelSpan span, const Tile& tile,
                     const SamplePattern& sp, bool depth_test, TileBuffers& buf) {
    const auto [xs, xe, ys, ye] = span;
    // Edge k, of vertex k's weight, runs from vertex i = k + 1 to j = k + 2 (Edge::make):
    // E(x, y) = dx (y - y_i) - dy (x - x_i). Relative to vertex i, over the box |E| <=
    // (|dx| + |dy|) (kSmall + 2) 256 with |dx|, |dy| <= kSmall 256: below 2^28, and the steps
    // of four pixels below 2^24, so 32 bits hold everything exactly.
    const int32_t ox = xs * kSubpixel + sp.ox[0], oy = ys * kSubpixel + sp.oy[0];
    __m128i w_row[3], step_x[3], step_y[3];
    int32_t a[3], bias[3];
    for (int k = 0; k < 3; ++k) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        int32_t dx = t.x[j] - t.x[i], dy = t.y[j] - t.y[i];
        bias[k] = (-dy > 0 || (dy == 0 && dx > 0)) ? 0 : -1;  // the top-left rule
        int32_t origin = dx * (oy - t.y[i]) - dy * (ox - t.x[i]) + bias[k];
        a[k] = -dy;
        int32_t ax = a[k] * kSubpixel;
        w_row[k] = _mm_add_epi32(_mm_set1_epi32(origin), _mm_set_epi32(3 * ax, 2 * ax, ax, 0));
        step_x[k] = _mm_set1_epi32(4 * ax);
        step_y[k] = _mm_set1_epi32(dx * kSubpixel);
    }
    // The depth plane (TriangleEdges::depth_gradient with these coefficients).
    double per_pixel = static_cast<double>(kSubpixel) * static_cast<double>(t.inv_area);
    double z1 = t.z[1] - t.z[0], z2 = t.z[2] - t.z[0];
    auto dzdx = static_cast<float>(
        (static_cast<double>(a[1]) * z1 + static_cast<double>(a[2]) * z2) * per_pixel);
    auto dzdy = static_cast<float>(
        (static_cast<double>(t.x[0] - t.x[2]) * z1 + static_cast<double>(t.x[1] - t.x[0]) * z2) *
        per_pixel);
    float z_origin = t.z[0] +
                     dzdx * static_cast<float>(static_cast<double>(ox - t.x[0]) / kSubpixel) +
                     dzdy * static_cast<float>(static_cast<double>(oy - t.y[0]) / kSubpixel);
    const __m128 z_steps = _mm_mul_ps(_mm_set1_ps(dzdx), _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f));
    const __m128 z_step4 = _mm_set1_ps(4.0f * dzdx);
    const int tw = tile.x1 - tile.x0;
    const __m128i lane = _mm_set_epi32(3, 2, 1, 0);
    const __m128i id4 = _mm_set1_epi32(static_cast<int32_t>(id));
    // The barycentrics the shading reads back: E / (2 area), without the fill rule's bias.
    const __m128i bias1 = _mm_set1_epi32(bias[1]), bias2 = _mm_set1_epi32(bias[2]);
    const __m128 inv_area = _mm_set1_ps(t.inv_area);
    auto blend = [](__m128 mask, __m128 yes, __m128 no) {  // yes where mask, else no
        return _mm_or_ps(_mm_and_ps(mask, yes), _mm_andnot_ps(mask, no));
    };
    for (int py = ys; py < ye; ++py) {
        __m128i w0 = w_row[0], w1 = w_row[1], w2 = w_row[2];
        __m128 z4 = _mm_add_ps(_mm_set1_ps(z_origin + dzdy * static_cast<float>(py - ys)), z_steps);
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
                __m128 l1 = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(w1, bias1)), inv_area);
                __m128 l2 = _mm_mul_ps(_mm_cvtepi32_ps(_mm_sub_epi32(w2, bias2)), inv_area);
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
                const __m128 steps = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f);
                const __m128i ids = _mm_set1_epi32(static_cast<int>(id));
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
                    for (; px + 4 <= x1; px += 4, i += 4, z += 4.0f * dz) {
                        __m128 z4 = _mm_add_ps(_mm_set1_ps(z), _mm_mul_ps(_mm_set1_ps(dz), steps));
                        __m128 d = _mm_loadu_ps(&buf.depth[i]);
                        __m128 m =
                            depth_test ? _mm_cmplt_ps(z4, d) : _mm_castsi128_ps(_mm_set1_epi32(-1));
                        if (_mm_movemask_ps(m) == 0) continue;
                        _mm_storeu_ps(&buf.depth[i],
                                      _mm_or_ps(_mm_and_ps(m, z4), _mm_andnot_ps(m, d)));
                        auto* tp = reinterpret_cast<__m128i*>(&buf.tri[i]);
                        __m128i mi = _mm_castps_si128(m);
                        _mm_storeu_si128(tp,
                                         _mm_or_si128(_mm_and_si128(mi, ids),
                                                      _mm_andnot_si128(mi, _mm_loadu_si128(tp))));
                        wrote = true;
                    }
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
                // The block's deepest sample may have come nearer: the max over its rows, four
                // lanes at a time (each row of the block is contiguous).
                __m128 deepest = _mm_set1_ps(-kInfinity);
                float tail = -kInfinity;
                int px0 = bx * kB, px1 = std::min(tw, (bx + 1) * kB);
                for (int py = tile.y0 + by * kB; py < std::min(tile.y1, tile.y0 + (by + 1) * kB);
                     ++py) {
                    const float* row =
                        buf.depth.data() + (static_cast<size_t>(py - tile.y0) * tw + px0) * S;
                    size_t n = static_cast<size_t>(px1 - px0) * S, i = 0;
                    for (; i + 4 <= n; i += 4) deepest = _mm_max_ps(deepest, _mm_loadu_ps(row + i));
                    for (; i < n; ++i) tail = std::max(tail, row[i]);
                }
                alignas(16) float lanes[4];
                _mm_store_ps(lanes, deepest);
                far = std::max({lanes[0], lanes[1], lanes[2], lanes[3], tail});
            }
        }
    }
}

/// What a pass does with the samples a triangle covers (OpenGL's depth and stencil state).

/// A stencil count's change per operation: Keep, IncrWrap and DecrWrap only (else 2).
int stencil_delta(StencilOp op) {
    return op == StencilOp::Keep       ? 0
           : op == StencilOp::IncrWrap ? 1
           : op == StencilOp::DecrWrap ? -1
                                       : 2;
}

/// The edge functions of four neighbouring pixels of a row, stepped four pixels at a time:
/// in 32-bit lanes where every value met fits (`kWide` false), else in 64-bit lanes, two to a
/// register (a shadow volume's sides reach the guard band). outside() is all ones in each
/// lane where one of the edges is negative.
template <bool kWide>
struct RowEdges {
    __m128i w[3][kWide ? 2 : 1], step[3], down[3];

    /// Edges at row sy from sx, each the edge's value plus its fill-rule bias; an edge left
    /// out of `crossing` counts as inside everywhere (zero, stepped by zero).
    RowEdges(const TriangleEdges& te, int64_t sx, int64_t sy, unsigned crossing) {
        for (int k = 0; k < 3; ++k) {
            const bool used = (crossing >> k) & 1u;
            const int64_t d = used ? te.e[k].a * kSubpixel : 0;
            const int64_t r = used ? te.e[k].b * kSubpixel : 0;
            const int64_t e = used ? te.e[k].at(sx, sy) + te.e[k].bias : 0;
            if constexpr (kWide) {
                w[k][0] = _mm_set_epi64x(e + d, e);
                w[k][1] = _mm_set_epi64x(e + 3 * d, e + 2 * d);
                step[k] = _mm_set1_epi64x(4 * d);
                down[k] = _mm_set1_epi64x(r);
            } else {
                w[k][0] =
                    _mm_set_epi32(static_cast<int32_t>(e + 3 * d), static_cast<int32_t>(e + 2 * d),
                                  static_cast<int32_t>(e + d), static_cast<int32_t>(e));
                step[k] = _mm_set1_epi32(static_cast<int32_t>(4 * d));
                down[k] = _mm_set1_epi32(static_cast<int32_t>(r));
            }
        }
    }
    __m128i outside() const {
        if constexpr (kWide) {
            // The sign of each 64-bit lane is in its upper half: those four halves, in order.
            const __m128i lo = _mm_or_si128(_mm_or_si128(w[0][0], w[1][0]), w[2][0]);
            const __m128i hi = _mm_or_si128(_mm_or_si128(w[0][1], w[1][1]), w[2][1]);
            const __m128 upper =
                _mm_shuffle_ps(_mm_castsi128_ps(lo), _mm_castsi128_ps(hi), _MM_SHUFFLE(3, 1, 3, 1));
            return _mm_srai_epi32(_mm_castps_si128(upper), 31);
        } else {
            return _mm_srai_epi32(_mm_or_si128(_mm_or_si128(w[0][0], w[1][0]), w[2][0]), 31);
        }
    }
    /// Four pixels to the right (`step`), or one row down (`down`).
    void next() { add(step); }
    void next_row() { add(down); }

private:
    void add(const __m128i (&by)[3]) {
        for (int k = 0; k < 3; ++k) {
            if constexpr (kWide) {
                w[k][0] = _mm_add_epi64(w[k][0], by[k]);
                w[k][1] = _mm_add_epi64(w[k][1], by[k]);
            } else {
                w[k][0] = _mm_add_epi32(w[k][0], by[k]);
            }
        }
    }
};

/// rasterize_plain's per-sample loop over one block, four pixels at a time, for what a shadow
/// volume's stencil pass asks (one sample per pixel, the stencil test Always, the pass and
/// depth-fail operations adding `delta_pass` and `delta_fail` with wrapping, no depth or item
/// written): the same coverage (edge functions exact, in 32-bit lanes where they fit, which
/// the caller says by `kWide`), the same depths (the same double-precision operations, in the
/// same order) and the same counts. `crossing`: the edges that cross the block (the others
/// hold it whole). `all_fail`: every sample fails the depth test.
template <bool kWide>
void count_block(const SetupTriangle& t, const TriangleEdges& te, double dzdx, double dzdy, int x0,
                 int x1, int y0, int y1, const Tile& tile, const SamplePattern& sp,
                 float depth_bias, int delta_pass, int delta_fail, unsigned crossing, bool all_fail,
                 TileBuffers& buf) {
    const int tw = tile.x1 - tile.x0;
    const __m128i lane = _mm_set_epi32(3, 2, 1, 0);
    const __m128d z0 = _mm_set1_pd(static_cast<double>(t.z[0]));
    const __m128d gx = _mm_set1_pd(dzdx), scale = _mm_set1_pd(1.0 / kSubpixel);
    const __m128 bias = _mm_set1_ps(depth_bias);
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128i dpass = _mm_set1_epi32(delta_pass), dfail = _mm_set1_epi32(delta_fail);
    const int64_t sx = static_cast<int64_t>(x0) * kSubpixel + sp.ox[0];
    RowEdges<kWide> row(te, sx, static_cast<int64_t>(y0) * kSubpixel + sp.oy[0], crossing);
    for (int py = y0; py < y1; ++py, row.next_row()) {
        const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[0];
        RowEdges<kWide> edges = row;
        // (dzdy (y - y0) / 256, the same for the row.)
        const __m128d ty = _mm_set1_pd(dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel);
        size_t i = static_cast<size_t>(py - tile.y0) * tw + (x0 - tile.x0);
        for (int px = x0; px < x1; px += 4, i += 4) {
            const __m128i in_span = _mm_cmplt_epi32(lane, _mm_set1_epi32(x1 - px));
            const __m128i covered = _mm_andnot_si128(edges.outside(), in_span);
            edges.next();
            if (_mm_movemask_epi8(covered) == 0) continue;
            __m128i pass = _mm_setzero_si128();
            if (!all_fail) {
                // z = (z0 + dzdx (x - x0) / 256) + dzdy (y - y0) / 256, per lane in double.
                const double dx =
                    static_cast<double>(static_cast<int64_t>(px) * kSubpixel + sp.ox[0] - t.x[0]);
                const __m128d xa = _mm_set_pd(dx + kSubpixel, dx),
                              xb = _mm_set_pd(dx + 3 * kSubpixel, dx + 2 * kSubpixel);
                const __m128d za =
                    _mm_add_pd(_mm_add_pd(z0, _mm_mul_pd(_mm_mul_pd(gx, xa), scale)), ty);
                const __m128d zb =
                    _mm_add_pd(_mm_add_pd(z0, _mm_mul_pd(_mm_mul_pd(gx, xb), scale)), ty);
                const __m128 z = _mm_movelh_ps(_mm_cvtpd_ps(za), _mm_cvtpd_ps(zb));
                const __m128 tested = _mm_add_ps(z, _mm_mul_ps(bias, _mm_andnot_ps(sign, z)));
                pass = _mm_castps_si128(_mm_cmplt_ps(tested, _mm_loadu_ps(&buf.depth[i])));
            }
            // Each lane's change, as bytes, added to the four counts (wrapping).
            const __m128i delta = _mm_and_si128(
                covered, _mm_or_si128(_mm_and_si128(pass, dpass), _mm_andnot_si128(pass, dfail)));
            const __m128i bytes =
                _mm_packs_epi16(_mm_packs_epi32(delta, delta), _mm_setzero_si128());
            int32_t counts;
            std::memcpy(&counts, &buf.stencil[i], 4);
            counts = _mm_cvtsi128_si32(_mm_add_epi8(_mm_cvtsi32_si128(counts), bytes));
            std::memcpy(&buf.stencil[i], &counts, 4);
        }
    }
}

/// rasterize_plain counts a row of blocks as one band where a triangle reaches fewer blocks of
/// it than this.
constexpr int kBandBlocks = 3;

/// Stage 5, the plain form a student can follow: per sample, the stencil test and its
/// operations around the depth test (stencil.h), and the depth written only when the state
/// says so. Used when the stencil is on or depth writes are off; the blocks' deepest depths
/// are left as they were (larger than the truth: safe). Two shortcuts per 8 x 8 block, which
/// shadow volumes' long sides need: a block no edge lets in is skipped, and so is a block
/// where every sample would pass the depth test and passing changes nothing (no depth or item
/// writes, the stencil's pass operation Keep): the triangle's farthest depth over the block is
/// nearer than the block's nearest stored depth (TileBuffers::block_near, when a pass keeps it).
/// And where the triangle's nearest depth over the block is behind the block's farthest,
/// every covered sample fails the depth test: the block is skipped when failing does nothing
/// (z-pass), else no depth is computed.
void rasterize_plain(uint32_t id, const SetupTriangle& t, const TriangleEdges& te, PixelSpan span,
                     const Tile& tile, const SamplePattern& sp, const PipelineState& state,
                     TileBuffers& buf) {
    const auto [xs, xe, ys, ye] = span;
    const StencilState& st = state.stencil;
    const StencilFace& face = t.front ? st.front : st.back;
    double dzdx, dzdy;
    te.depth_gradient(t, dzdx, dzdy);
    const int tw = tile.x1 - tile.x0, S = sp.count, kB = TileBuffers::kBlock, bw = kTile / kB;
    const bool block_depths = state.depth_test && !state.depth_write && !buf.block_near.empty();
    const bool passing_is_idle =
        block_depths && !state.write_items &&
        (!st.enabled || (face.pass == StencilOp::Keep && face.func == StencilFunc::Always));
    // A shadow volume's count: four pixels at a time (count_block).
    const bool counts_only = S == 1 && st.enabled && state.depth_test && !state.depth_write &&
                             !state.write_items && face.func == StencilFunc::Always &&
                             st.write_mask == 0xff && stencil_delta(face.pass) != 2 &&
                             stencil_delta(face.depth_fail) != 2;
    const bool failing_is_idle =
        block_depths &&
        (!st.enabled || (face.depth_fail == StencilOp::Keep && face.func == StencilFunc::Always));
    if (counts_only && t.small) {
        // A small triangle (a cap of a shadow volume): its edge functions over its bounding
        // box fit in 32 bits; counted four pixels at a time over the box at once, without the
        // per-block tests, which would cost more than they save.
        count_block<false>(t, te, dzdx, dzdy, xs, xe, ys, ye, tile, sp, state.depth_bias,
                           stencil_delta(face.pass), stencil_delta(face.depth_fail), 7u, false,
                           buf);
        return;
    }
    // The depth plane at pixel position (px, py), in pixels.
    const double x0f = static_cast<double>(t.x[0]) / kSubpixel,
                 y0f = static_cast<double>(t.y[0]) / kSubpixel;
    auto plane = [&](double px, double py) {
        return t.z[0] + dzdx * (px - x0f) + dzdy * (py - y0f);
    };
    if (block_depths) {
        // The same tests over the whole span first, against the tile's nearest and farthest
        // stored depths: a long side of a volume crosses many tiles wholly behind the scene.
        const double c[4] = {plane(xs, ys), plane(xe, ys), plane(xs, ye), plane(xe, ye)};
        auto zmax = static_cast<float>(std::max({c[0], c[1], c[2], c[3]}));
        auto zmin = static_cast<float>(std::min({c[0], c[1], c[2], c[3]}));
        if (passing_is_idle && zmax + state.depth_bias * std::abs(zmax) < buf.tile_near) return;
        if (failing_is_idle && zmin >= buf.tile_far) return;
    }
    // What the depth test does over the rectangle [x0, x1) x [y0, y1) of pixels, whose stored
    // depths lie in [near, far]: nothing to be done (every sample passes and passing does
    // nothing, or fails and failing does nothing), every sample fails, or either.
    enum class DepthTest { Idle, AllFail, Either };
    auto depth_over = [&](int x0, int x1, int y0, int y1, float near, float far) {
        const double c[4] = {plane(x0, y0), plane(x1, y0), plane(x0, y1), plane(x1, y1)};
        auto zmax = static_cast<float>(std::max({c[0], c[1], c[2], c[3]}));
        auto zmin = static_cast<float>(std::min({c[0], c[1], c[2], c[3]}));
        // (z + bias |z| grows with z: the corners bound it too.)
        if (passing_is_idle && zmax + state.depth_bias * std::abs(zmax) < near)
            return DepthTest::Idle;
        if (zmin >= far) return failing_is_idle ? DepthTest::Idle : DepthTest::AllFail;
        return DepthTest::Either;
    };
    // The edges over the same rectangle: outside one at all four corners (nothing covered),
    // the edges with the rectangle on both sides, and the largest |edge function| that
    // count_block's four-wide steps can meet there.
    struct EdgesOver {
        bool outside = false;
        unsigned crossing = 0;
        int64_t reach = 0;
    };
    auto edges_over = [&](int x0, int x1, int y0, int y1) {
        const int64_t xa = static_cast<int64_t>(x0) * kSubpixel,
                      xb = static_cast<int64_t>(x1) * kSubpixel - 1;
        const int64_t ya = static_cast<int64_t>(y0) * kSubpixel,
                      yb = static_cast<int64_t>(y1) * kSubpixel - 1;
        EdgesOver r;
        for (int k = 0; k < 3; ++k) {
            const Edge& e = te.e[k];
            const int64_t c[4] = {e.at(xa, ya), e.at(xb, ya), e.at(xa, yb), e.at(xb, yb)};
            r.outside = r.outside || std::max({c[0], c[1], c[2], c[3]}) + e.bias < 0;
            if (std::min({c[0], c[1], c[2], c[3]}) + e.bias >= 0) continue;
            r.crossing |= 1u << k;
            for (int64_t v : c)
                r.reach = std::max(r.reach, std::abs(v) + 8 * std::abs(e.a) * kSubpixel + 1);
        }
        return r;
    };
    // -1 / (a kSubpixel) per edge: E(x, y) = 0 at x = -E(0, y) / a, in pixels.
    double to_x[3];
    for (int k = 0; k < 3; ++k)
        to_x[k] = te.e[k].a == 0 ? 0.0 : -1.0 / (static_cast<double>(te.e[k].a) * kSubpixel);
    for (int by = (ys - tile.y0) / kB; by <= (ye - 1 - tile.y0) / kB; ++by) {
        // The columns of this row of blocks the triangle can reach: each edge bounds x on one
        // side over the rows' y range (a long, thin shadow-volume side crosses a tile's
        // bounding box on a few blocks of each row). A pixel of margin on each side covers
        // the rounding.
        const int ry0 = std::max(ys, tile.y0 + by * kB),
                  ry1 = std::min(ye, tile.y0 + (by + 1) * kB);
        double left = -1e30, right = 1e30;
        for (int k = 0; k < 3; ++k) {
            const Edge& e = te.e[k];
            const double ya = static_cast<double>(ry0) * kSubpixel,
                         yb = static_cast<double>(ry1) * kSubpixel;
            const double ea = static_cast<double>(e.b) * ya + static_cast<double>(e.c + e.bias),
                         eb = static_cast<double>(e.b) * yb + static_cast<double>(e.c + e.bias);
            if (e.a == 0) {
                if (std::max(ea, eb) < 0.0) right = -1e30;  // the whole row is outside
            } else if (e.a > 0) {  // inside where x >= -E(0, y) / a, for some y of the rows
                left = std::max(left, std::min(ea * to_x[k], eb * to_x[k]));
            } else {  // inside where x <= -E(0, y) / a
                right = std::min(right, std::max(ea * to_x[k], eb * to_x[k]));
            }
        }
        const int cx0 = std::max(xs, static_cast<int>(std::max(left - 1.0, -1e9)));
        const int cx1 = std::min(xe, static_cast<int>(std::min(right + 2.0, 1e9)));
        if (cx0 >= cx1) continue;
        const int bx0 = (cx0 - tile.x0) / kB, bx1 = (cx1 - 1 - tile.x0) / kB;
        if (counts_only && bx1 - bx0 < kBandBlocks) {
            // A thin triangle (a volume's side) crosses this row of blocks on a few of them:
            // the whole band at once, against the blocks' depth range together.
            float near = kInfinity, far = -kInfinity;
            for (int bx = bx0; bx <= bx1; ++bx) {
                near = std::min(near, buf.block_near[static_cast<size_t>(by) * bw + bx]);
                far = std::max(far, buf.block_far[static_cast<size_t>(by) * bw + bx]);
            }
            const DepthTest test = depth_over(cx0, cx1, ry0, ry1, near, far);
            if (test == DepthTest::Idle) continue;
            const EdgesOver edges = edges_over(cx0, cx1, ry0, ry1);
            if (edges.outside) continue;
            const int dp = stencil_delta(face.pass), df = stencil_delta(face.depth_fail);
            const bool all_fail = test == DepthTest::AllFail;
            if (edges.reach < (int64_t{1} << 30)) {
                count_block<false>(t, te, dzdx, dzdy, cx0, cx1, ry0, ry1, tile, sp,
                                   state.depth_bias, dp, df, edges.crossing, all_fail, buf);
            } else {
                count_block<true>(t, te, dzdx, dzdy, cx0, cx1, ry0, ry1, tile, sp, state.depth_bias,
                                  dp, df, edges.crossing, all_fail, buf);
            }
            continue;
        }
        for (int bx = bx0; bx <= bx1; ++bx) {
            const int x0 = std::max(xs, tile.x0 + bx * kB),
                      x1 = std::min(xe, tile.x0 + (bx + 1) * kB);
            const int y0 = ry0, y1 = ry1;
            bool all_fail = false;
            if (block_depths) {
                const size_t b = static_cast<size_t>(by) * bw + bx;
                const DepthTest test =
                    depth_over(x0, x1, y0, y1, buf.block_near[b], buf.block_far[b]);
                if (test == DepthTest::Idle) continue;
                all_fail = test == DepthTest::AllFail;
            }
            const EdgesOver edges = edges_over(x0, x1, y0, y1);
            if (edges.outside) continue;
            const unsigned crossing = edges.crossing;
            const int64_t reach = edges.reach;
            const bool inside = crossing == 0;
            if (all_fail && inside && st.enabled && face.func == StencilFunc::Always) {
                // Every sample of the block covered and failing: one operation on a run of
                // bytes per row (a shadow volume's count behind the scene, the common case).
                for (int py = y0; py < y1; ++py) {
                    uint8_t* row = buf.stencil.data() +
                                   (static_cast<size_t>(py - tile.y0) * tw + (x0 - tile.x0)) * S;
                    const size_t n = static_cast<size_t>(x1 - x0) * S;
                    if (face.depth_fail == StencilOp::IncrWrap && st.write_mask == 0xff) {
                        for (size_t k = 0; k < n; ++k) row[k] = static_cast<uint8_t>(row[k] + 1);
                    } else if (face.depth_fail == StencilOp::DecrWrap && st.write_mask == 0xff) {
                        for (size_t k = 0; k < n; ++k) row[k] = static_cast<uint8_t>(row[k] - 1);
                    } else {
                        for (size_t k = 0; k < n; ++k)
                            row[k] = stencil_apply(face.depth_fail, row[k], st.ref, st.write_mask);
                    }
                }
                continue;
            }
            if (counts_only) {
                const int dp = stencil_delta(face.pass), df = stencil_delta(face.depth_fail);
                if (reach < (int64_t{1} << 30)) {
                    count_block<false>(t, te, dzdx, dzdy, x0, x1, y0, y1, tile, sp,
                                       state.depth_bias, dp, df, crossing, all_fail, buf);
                } else {
                    count_block<true>(t, te, dzdx, dzdy, x0, x1, y0, y1, tile, sp, state.depth_bias,
                                      dp, df, crossing, all_fail, buf);
                }
                continue;
            }
            // Per sample: coverage, the stencil test, the depth test (none where all fail).
            for (int py = y0; py < y1; ++py) {
                for (int s = 0; s < S; ++s) {
                    const int64_t sx = static_cast<int64_t>(x0) * kSubpixel + sp.ox[s];
                    const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[s];
                    int64_t w0 = te.e[0].at(sx, sy) + te.e[0].bias,
                            w1 = te.e[1].at(sx, sy) + te.e[1].bias,
                            w2 = te.e[2].at(sx, sy) + te.e[2].bias;
                    const int64_t d0 = te.e[0].a * kSubpixel, d1 = te.e[1].a * kSubpixel,
                                  d2 = te.e[2].a * kSubpixel;
                    size_t i = (static_cast<size_t>(py - tile.y0) * tw + (x0 - tile.x0)) * S + s;
                    for (int px = x0; px < x1; ++px, w0 += d0, w1 += d1, w2 += d2, i += S) {
                        if ((w0 | w1 | w2) < 0) continue;
                        uint8_t unused = 0;
                        uint8_t& stencil = st.enabled ? buf.stencil[i] : unused;
                        if (st.enabled && !stencil_test(face.func, st.ref, stencil, st.read_mask)) {
                            stencil = stencil_apply(face.fail, stencil, st.ref, st.write_mask);
                            continue;
                        }
                        if (all_fail) {
                            if (st.enabled)
                                stencil =
                                    stencil_apply(face.depth_fail, stencil, st.ref, st.write_mask);
                            continue;
                        }
                        const int64_t x = static_cast<int64_t>(px) * kSubpixel + sp.ox[s];
                        auto z = static_cast<float>(
                            t.z[0] + dzdx * static_cast<double>(x - t.x[0]) / kSubpixel +
                            dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel);
                        if (state.depth_test &&
                            !(z + state.depth_bias * std::abs(z) < buf.depth[i])) {
                            if (st.enabled)
                                stencil =
                                    stencil_apply(face.depth_fail, stencil, st.ref, st.write_mask);
                            continue;
                        }
                        if (st.enabled)
                            stencil = stencil_apply(face.pass, stencil, st.ref, st.write_mask);
                        if (state.depth_write) buf.depth[i] = z;
                        buf.tri[i] = id;
                    }
                }
            }
        }
    }
}

/// Stage 5 for one triangle in one tile: the small-triangle path or the general one.
void draw_triangle(uint32_t id, const SetupTriangle& t, const Tile& tile, const SamplePattern& sp,
                   const PipelineState& state, TileBuffers& buf) {
    const bool depth_test = state.depth_test;
    PixelSpan span{std::max(t.x0(), tile.x0), std::min(t.x1(), tile.x1), std::max(t.y0(), tile.y0),
                   std::min(t.y1(), tile.y1)};
    if (span.xs >= span.xe || span.ys >= span.ye) return;
    if (state.stencil.enabled || !state.depth_write) {
        rasterize_plain(id, t, TriangleEdges(t), span, tile, sp, state, buf);
    } else if (t.small && sp.count == 1) {
        if (state.write_items) {
            rasterize_small<true>(id, t, span, tile, sp, depth_test, buf);
        } else {
            rasterize_small<false>(id, t, span, tile, sp, depth_test, buf);
        }
    } else {
        rasterize(id, t, TriangleEdges(t), span, tile, sp, depth_test, buf);
    }
}

/// Perspective-correct weights of a sample: the screen barycentrics over w (q), and

}  // namespace

SamplePattern sample_pattern(int spp, uint64_t seed, int first, int count) {
    SamplePattern p;
    p.count = count;
    for (int s = 0; s < count; ++s) {
        int k = first + s;
        vec2 o(0.5f);
        if (spp > 1) {
            Rng rng(seed * 0x9e3779b97f4a7c15ULL + static_cast<uint64_t>(k), 0x5ca1ab1eULL);
            o = stratified_sample(k, spp, vec2(rng.next_float(), rng.next_float()));
        }
        p.ox[s] = std::min(kSubpixel - 1, static_cast<int32_t>(o.x * kSubpixel));
        p.oy[s] = std::min(kSubpixel - 1, static_cast<int32_t>(o.y * kSubpixel));
        p.offset[s] = vec2(static_cast<float>(p.ox[s]), static_cast<float>(p.oy[s])) /
                      static_cast<float>(kSubpixel);
    }
    return p;
}

void rasterize_tile(const FrameState& f, const Tile& tile, const SamplePattern& sp,
                    const PipelineState& state, TileBuffers& buf) {
    size_t ti = static_cast<size_t>(tile.y0 / kTile) * f.tiles_x + tile.x0 / kTile;
    for (const FrameState::Bins& b : f.bins) {
        const uint32_t end = b.start[ti + 1];
        for (uint32_t k = b.start[ti]; k < end; ++k) {
            // The triangles of a tile are scattered over the frame's: fetch ahead.
            constexpr uint32_t kAhead = 8;
            if (k + kAhead < end)
                _mm_prefetch(reinterpret_cast<const char*>(&f.tri(b.ids[k + kAhead])), _MM_HINT_T0);
            draw_triangle(b.ids[k], f.tri(b.ids[k]), tile, sp, state, buf);
        }
    }
}

}  // namespace svetlo::raster
