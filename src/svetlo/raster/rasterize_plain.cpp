// Stage 5's plain form, for passes with the stencil on or depth writes off: per sample, the
// stencil test and its operations around the depth test (stencil.h), with the shortcuts a
// shadow volume's stencil count needs (its long sides, its small caps), each giving the same
// counts as the count sample by sample.
//
// The shadow volume's stencil count over a block has a plain twin (count_block below, under
// !SVETLO_SIMD: the statement) and an SSE form (four pixels at once; AVX2: eight, in
// stencil_count_avx2.cpp), which give the same counts.
#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <algorithm>
#include <cstring>

#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

namespace {

/// A stencil count's change per operation: Keep, IncrWrap and DecrWrap only (else 2).
int stencil_delta(StencilOp op) {
    return op == StencilOp::Keep       ? 0
           : op == StencilOp::IncrWrap ? 1
           : op == StencilOp::DecrWrap ? -1
                                       : 2;
}

#if !SVETLO_SIMD
/// rasterize_plain's per-sample loop over one block, for what a shadow volume's stencil pass
/// asks: one sample per pixel, the stencil test Always, the pass and depth-fail operations
/// adding `delta_pass` and `delta_fail` with wrapping, no depth or item written. `crossing`:
/// the edges that cross the block (the others hold it whole). `all_fail`: every sample fails
/// the depth test. (`kWide` and `avx2` choose the SSE and AVX2 forms' lanes: unused here.)
template <bool kWide>
void count_block(const SetupTriangle& t, const TriangleEdges& te, double dzdx, double dzdy, int x0,
                 int x1, int y0, int y1, const Tile& tile, const SamplePattern& sp,
                 float depth_bias, int delta_pass, int delta_fail, unsigned crossing, bool all_fail,
                 bool /*avx2*/, TileBuffers& buf) {
    const int tw = tile.x1 - tile.x0;
    const int64_t sx = static_cast<int64_t>(x0) * kSubpixel + sp.ox[0];
    const int64_t sy0 = static_cast<int64_t>(y0) * kSubpixel + sp.oy[0];
    CountEdge edge[3];
    for (int k = 0; k < 3; ++k) edge[k] = count_edge(te, k, sx, sy0, crossing);
    for (int py = y0; py < y1; ++py) {
        const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[0];
        const double ty = dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel;
        size_t i = static_cast<size_t>(py - tile.y0) * tw + (x0 - tile.x0);
        for (int px = x0; px < x1; ++px, ++i) {
            bool covered = true;
            for (const CountEdge& e : edge)
                covered &= e.value + e.right * (px - x0) + e.down * (py - y0) >= 0;
            if (!covered) continue;
            int delta = delta_fail;
            if (!all_fail) {
                // z = (z0 + dzdx (x - x0) / 256) + dzdy (y - y0) / 256, in double, then the
                // bias slope-scaled by |z|.
                const auto dx =
                    static_cast<double>(static_cast<int64_t>(px) * kSubpixel + sp.ox[0] - t.x[0]);
                const auto z = static_cast<float>(
                    (static_cast<double>(t.z[0]) + dzdx * dx * (1.0 / kSubpixel)) + ty);
                if (z + depth_bias * std::fabs(z) < buf.depth[i]) delta = delta_pass;
            }
            buf.stencil[i] = static_cast<uint8_t>(buf.stencil[i] + delta);  // wrapping
        }
    }
}
#else
/// The edge functions of four neighbouring pixels of a row, stepped four pixels at a time:
/// in 32-bit lanes where every value met fits (`kWide` false), else in 64-bit lanes, two to a
/// register (a shadow volume's sides reach the guard band). outside() is all ones in each
/// lane where one of the edges is negative.
template <bool kWide>
struct RowEdges {
    __m128i w[3][kWide ? 2 : 1], step[3], down[3];

    /// Edges at row sy from sx (count_edge).
    RowEdges(const TriangleEdges& te, int64_t sx, int64_t sy, unsigned crossing) {
        for (int k = 0; k < 3; ++k) {
            const auto [e, d, r] = count_edge(te, k, sx, sy, crossing);
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

/// count_block's SSE form (its twin is above, under !SVETLO_SIMD): rasterize_plain's per-sample
/// loop over one block, four pixels at a time, for what a shadow
/// volume's stencil pass asks (one sample per pixel, the stencil test Always, the pass and
/// depth-fail operations adding `delta_pass` and `delta_fail` with wrapping, no depth or item
/// written): the same coverage (edge functions exact, in 32-bit lanes where they fit, which
/// the caller says by `kWide`), the same depths (the same double-precision operations, in the
/// same order) and the same counts. `crossing`: the edges that cross the block (the others
/// hold it whole). `all_fail`: every sample fails the depth test. `avx2`: in count_block_avx2.
template <bool kWide>
void count_block(const SetupTriangle& t, const TriangleEdges& te, double dzdx, double dzdy, int x0,
                 int x1, int y0, int y1, const Tile& tile, const SamplePattern& sp,
                 float depth_bias, int delta_pass, int delta_fail, unsigned crossing, bool all_fail,
                 bool avx2, TileBuffers& buf) {
    if (avx2) {
        count_block_avx2(t, te, dzdx, dzdy, x0, x1, y0, y1, tile, sp, depth_bias, delta_pass,
                         delta_fail, crossing, all_fail, kWide, buf);
        return;
    }
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
#endif

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
                     bool avx2, TileBuffers& buf) {
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
                           avx2, buf);
        return;
    }
    // The depth plane at pixel position (px, py), in pixels.
    const double x0f = static_cast<double>(t.x[0]) / kSubpixel,
                 y0f = static_cast<double>(t.y[0]) / kSubpixel;
    auto plane = [&](double px, double py) {
        return t.z[0] + dzdx * (px - x0f) + dzdy * (py - y0f);
    };
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
    // count_block over a rectangle, in 32-bit lanes where its edge functions fit.
    auto count = [&](int x0, int x1, int y0, int y1, const EdgesOver& edges, bool all_fail) {
        const int dp = stencil_delta(face.pass), df = stencil_delta(face.depth_fail);
        if (edges.reach < (int64_t{1} << 30)) {
            count_block<false>(t, te, dzdx, dzdy, x0, x1, y0, y1, tile, sp, state.depth_bias, dp,
                               df, edges.crossing, all_fail, avx2, buf);
        } else {
            count_block<true>(t, te, dzdx, dzdy, x0, x1, y0, y1, tile, sp, state.depth_bias, dp, df,
                              edges.crossing, all_fail, avx2, buf);
        }
    };
    // The same depth tests over the whole span first, against the tile's nearest and farthest
    // stored depths: a long side of a volume crosses many tiles wholly behind the scene.
    if (block_depths && depth_over(xs, xe, ys, ye, buf.tile_near, buf.tile_far) == DepthTest::Idle)
        return;
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
            if (!edges.outside) count(cx0, cx1, ry0, ry1, edges, test == DepthTest::AllFail);
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
            if (all_fail && edges.crossing == 0 && st.enabled && face.func == StencilFunc::Always) {
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
                count(x0, x1, y0, y1, edges, all_fail);
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

}  // namespace

void rasterize_tile_plain(const FrameState& f, const Tile& tile, const SamplePattern& sp,
                          const PipelineState& state, TileBuffers& buf) {
    for_each_binned(f, tile, [&](uint32_t id, const SetupTriangle& t) {
        const PixelSpan span = span_in(t, tile);
        if (!span.empty())
            rasterize_plain(id, t, TriangleEdges(t), span, tile, sp, state, f.avx2, buf);
    });
}

}  // namespace svetlo::raster
