// A shadow volume's stencil count with AVX2 (count_block_avx2 in pipeline.h): stencil_count.cpp's
// count_block (its twin), 4 x 2 pixels at a time instead of 4 x 1, with the same coverage
// (the same exact edge functions), the same depths (the same double-precision operations in
// the same order) and so the same counts. Used only where avx2_available(). The target is set
// by pragma after the headers, as in simd_shading_avx2.cpp.
#include <immintrin.h>

#include <cstring>

#include "svetlo/raster/pipeline.h"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace svetlo::raster {

namespace {

// Lanes 0-3: pixels 0-3 of a row of the block; 4-7: of the row below (functions, not
// globals: a global's initialiser would not be built for AVX2).
__m256i column_of_lanes() { return _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3); }
__m256i row_of_lanes() { return _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1); }

/// The three edge functions over a block of 4 x 2 pixels (count_edge), in 32-bit lanes
/// (`kWide` false: the caller knows every value met fits) or in 64-bit lanes, a register per
/// row.
template <bool kWide>
struct BlockEdges {
    __m256i w[3][kWide ? 2 : 1], step[3], down[3];

    BlockEdges(const TriangleEdges& te, int64_t sx, int64_t sy, unsigned crossing) {
        for (int k = 0; k < 3; ++k) {
            const auto [e, a, b] = count_edge(te, k, sx, sy, crossing);
            if constexpr (kWide) {
                w[k][0] = _mm256_setr_epi64x(e, e + a, e + 2 * a, e + 3 * a);
                w[k][1] = _mm256_add_epi64(w[k][0], _mm256_set1_epi64x(b));
                step[k] = _mm256_set1_epi64x(4 * a);
                down[k] = _mm256_set1_epi64x(2 * b);
            } else {
                // (Modulo 2^32, as the caller's 64-bit values cast: exact where they fit.)
                const auto a32 = static_cast<int32_t>(a), b32 = static_cast<int32_t>(b);
                w[k][0] = _mm256_add_epi32(
                    _mm256_set1_epi32(static_cast<int32_t>(e)),
                    _mm256_add_epi32(_mm256_mullo_epi32(column_of_lanes(), _mm256_set1_epi32(a32)),
                                     _mm256_mullo_epi32(row_of_lanes(), _mm256_set1_epi32(b32))));
                step[k] = _mm256_set1_epi32(static_cast<int32_t>(4 * a));
                down[k] = _mm256_set1_epi32(static_cast<int32_t>(2 * b));
            }
        }
    }
    /// All ones in each of the eight 32-bit lanes where an edge is negative.
    __m256i outside() const {
        if constexpr (kWide) {
            const __m256i zero = _mm256_setzero_si256();
            const __m256i r0 = _mm256_cmpgt_epi64(
                zero, _mm256_or_si256(_mm256_or_si256(w[0][0], w[1][0]), w[2][0]));
            const __m256i r1 = _mm256_cmpgt_epi64(
                zero, _mm256_or_si256(_mm256_or_si256(w[0][1], w[1][1]), w[2][1]));
            // The low halves of row 0's lanes into lanes 0-3, of row 1's into 4-7.
            const __m256i lo =
                _mm256_permutevar8x32_epi32(r0, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6));
            const __m256i hi =
                _mm256_permutevar8x32_epi32(r1, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6));
            return _mm256_blend_epi32(lo, hi, 0xF0);
        } else {
            return _mm256_srai_epi32(_mm256_or_si256(_mm256_or_si256(w[0][0], w[1][0]), w[2][0]),
                                     31);
        }
    }
    /// Four pixels to the right (`step`), or two rows down (`down`).
    void next() { add(step); }
    void next_rows() { add(down); }

private:
    void add(const __m256i (&by)[3]) {
        for (int k = 0; k < 3; ++k) {
            for (__m256i& v : w[k])
                v = kWide ? _mm256_add_epi64(v, by[k]) : _mm256_add_epi32(v, by[k]);
        }
    }
};

template <bool kWide>
void count(const StencilCount& c, PixelSpan r, unsigned crossing, bool all_fail, TileBuffers& buf) {
    const auto& [t, te, dzdx, dzdy, tile, sp, depth_bias, delta_pass, delta_fail] = c;
    const auto [x0, x1, y0, y1] = r;
    const int tw = tile.x1 - tile.x0;
    const __m256d z0 = _mm256_set1_pd(static_cast<double>(t.z[0]));
    const __m256d gx = _mm256_set1_pd(dzdx), scale = _mm256_set1_pd(1.0 / kSubpixel);
    const __m256d column = _mm256_setr_pd(0.0, kSubpixel, 2.0 * kSubpixel, 3.0 * kSubpixel);
    const __m256 bias = _mm256_set1_ps(depth_bias), sign = _mm256_set1_ps(-0.0f);
    const __m256i dpass = _mm256_set1_epi32(delta_pass), dfail = _mm256_set1_epi32(delta_fail);
    const int64_t sx = static_cast<int64_t>(x0) * kSubpixel + sp.ox[0];
    BlockEdges<kWide> rows(te, sx, static_cast<int64_t>(y0) * kSubpixel + sp.oy[0], crossing);
    for (int py = y0; py < y1; py += 2) {
        // (dzdy (y - y0) / 256 per row, the same for the row.)
        const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[0];
        const __m256d ty0 = _mm256_set1_pd(dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel);
        const __m256d ty1 =
            _mm256_set1_pd(dzdy * static_cast<double>(sy + kSubpixel - t.y[0]) / kSubpixel);
        const __m256i rows_in = _mm256_cmpgt_epi32(_mm256_set1_epi32(y1 - py), row_of_lanes());
        const size_t row0 = static_cast<size_t>(py - tile.y0) * tw;
        const size_t row1 = py + 1 < y1 ? row0 + static_cast<size_t>(tw) : row0;
        BlockEdges<kWide> edges = rows;
        for (int px = x0; px < x1; px += 4) {
            const __m256i in = _mm256_and_si256(
                rows_in, _mm256_cmpgt_epi32(_mm256_set1_epi32(x1 - px), column_of_lanes()));
            const __m256i covered = _mm256_andnot_si256(edges.outside(), in);
            edges.next();
            // (Where no depth is needed, without a branch: whether a block of a thin side is
            // covered is hard to predict, and adding nothing is cheap.)
            if (!all_fail && _mm256_testz_si256(covered, covered)) continue;
            const size_t i0 = row0 + static_cast<size_t>(px - tile.x0),
                         i1 = row1 + static_cast<size_t>(px - tile.x0);
            __m256i pass = _mm256_setzero_si256();
            if (!all_fail) {
                // z = (z0 + dzdx (x - x0) / 256) + dzdy (y - y0) / 256, per lane in double.
                const double dx =
                    static_cast<double>(static_cast<int64_t>(px) * kSubpixel + sp.ox[0] - t.x[0]);
                const __m256d xs = _mm256_add_pd(_mm256_set1_pd(dx), column);
                const __m256d along =
                    _mm256_add_pd(z0, _mm256_mul_pd(_mm256_mul_pd(gx, xs), scale));
                const __m256 z = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_add_pd(along, ty1)),
                                                 _mm256_cvtpd_ps(_mm256_add_pd(along, ty0)));
                const __m256 tested =
                    _mm256_add_ps(z, _mm256_mul_ps(bias, _mm256_andnot_ps(sign, z)));
                const __m256 stored = _mm256_loadu2_m128(&buf.depth[i1], &buf.depth[i0]);
                pass = _mm256_castps_si256(_mm256_cmp_ps(tested, stored, _CMP_LT_OQ));
            }
            // Each lane's change, as bytes, added to the counts (wrapping): the second row's
            // four first (where there is none it is the first row's, unchanged).
            const __m256i delta = _mm256_and_si256(covered, _mm256_blendv_epi8(dfail, dpass, pass));
            const __m128i d16 =
                _mm_packs_epi32(_mm256_castsi256_si128(delta), _mm256_extracti128_si256(delta, 1));
            const __m128i bytes = _mm_packs_epi16(d16, d16);  // row 0 in bytes 0-3, row 1 in 4-7
            int32_t c0, c1;
            std::memcpy(&c0, &buf.stencil[i0], 4);
            std::memcpy(&c1, &buf.stencil[i1], 4);
            c1 = _mm_cvtsi128_si32(_mm_add_epi8(_mm_cvtsi32_si128(c1), _mm_srli_si128(bytes, 4)));
            c0 = _mm_cvtsi128_si32(_mm_add_epi8(_mm_cvtsi32_si128(c0), bytes));
            std::memcpy(&buf.stencil[i1], &c1, 4);
            std::memcpy(&buf.stencil[i0], &c0, 4);
        }
        rows.next_rows();
    }
}

}  // namespace

void count_block_avx2(const StencilCount& c, PixelSpan r, unsigned crossing, bool all_fail,
                      bool wide, TileBuffers& buf) {
    if (wide) {
        count<true>(c, r, crossing, all_fail, buf);
    } else {
        count<false>(c, r, crossing, all_fail, buf);
    }
}

}  // namespace svetlo::raster

#pragma GCC pop_options
