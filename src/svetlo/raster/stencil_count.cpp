// A shadow volume's stencil count (docs/shadows.md): the pass that adds, at every pixel a
// volume's face covers, +1 or -1 by the face's side and whether the depth test passes (z-pass)
// or fails (z-fail), wrapping. rasterize_stencil.cpp's per-sample loop states what it does;
// this is that loop for the count alone, over a rectangle of a tile, where the stencil test
// is Always and nothing else is written.
//
// count_block has a plain twin (under !SVETLO_SIMD: the statement) and an SSE form (four
// pixels at once; AVX2: eight, in stencil_count_avx2.cpp), which give the same counts.
#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <cmath>
#include <cstring>

#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

namespace {

#if !SVETLO_SIMD
/// The count over one rectangle of pixels, sample by sample: what a shadow volume's stencil
/// pass asks: one sample per pixel, the stencil test Always, the pass and depth-fail operations
/// adding `delta_pass` and `delta_fail` with wrapping, no depth or item written. `crossing`:
/// the edges that cross the block (the others hold it whole). `all_fail`: every sample fails
/// the depth test. (`kWide` and `avx2` choose the SSE and AVX2 forms' lanes: unused here.)
template <bool kWide>
void count_block(const StencilCount& c, PixelSpan r, unsigned crossing, bool all_fail,
                 bool /*avx2*/, TileBuffers& buf) {
    const auto& [t, te, dzdx, dzdy, tile, sp, depth_bias, delta_pass, delta_fail] = c;
    const auto [x0, x1, y0, y1] = r;
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

/// count_block's SSE form (its twin is above, under !SVETLO_SIMD): the count over one
/// rectangle, four pixels at a time, for what a shadow
/// volume's stencil pass asks (one sample per pixel, the stencil test Always, the pass and
/// depth-fail operations adding `delta_pass` and `delta_fail` with wrapping, no depth or item
/// written): the same coverage (edge functions exact, in 32-bit lanes where they fit, which
/// the caller says by `kWide`), the same depths (the same double-precision operations, in the
/// same order) and the same counts. `crossing`: the edges that cross the block (the others
/// hold it whole). `all_fail`: every sample fails the depth test. `avx2`: in count_block_avx2.
template <bool kWide>
void count_block(const StencilCount& c, PixelSpan r, unsigned crossing, bool all_fail, bool avx2,
                 TileBuffers& buf) {
    if (avx2) {
        count_block_avx2(c, r, crossing, all_fail, kWide, buf);
        return;
    }
    const auto& [t, te, dzdx, dzdy, tile, sp, depth_bias, delta_pass, delta_fail] = c;
    const auto [x0, x1, y0, y1] = r;
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

}  // namespace

void count_stencil(const StencilCount& c, PixelSpan r, unsigned crossing, int64_t reach,
                   bool all_fail, bool avx2, TileBuffers& buf) {
    if (reach < (int64_t{1} << 30)) {
        count_block<false>(c, r, crossing, all_fail, avx2, buf);
    } else {
        count_block<true>(c, r, crossing, all_fail, avx2, buf);
    }
}

}  // namespace svetlo::raster
