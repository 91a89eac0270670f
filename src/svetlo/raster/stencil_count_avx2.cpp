// A shadow volume's stencil count with AVX2 (count_block_avx2 in pipeline.h): rasterize_plain's
// count_block in 32-bit lanes, 4 x 2 pixels at a time instead of 4 x 1, with the same coverage
// (the same exact edge functions), the same depths (the same double-precision operations in
// the same order) and so the same counts. Used only where avx2_available(). The target is set
// by pragma after the headers, as in simd_shading_avx2.cpp.
#include <immintrin.h>

#include <cstring>

#include "svetlo/raster/pipeline.h"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace svetlo::raster {

void count_block_avx2(const SetupTriangle& t, const TriangleEdges& te, double dzdx, double dzdy,
                      int x0, int x1, int y0, int y1, const Tile& tile, const SamplePattern& sp,
                      float depth_bias, int delta_pass, int delta_fail, unsigned crossing,
                      bool all_fail, TileBuffers& buf) {
    const int tw = tile.x1 - tile.x0;
    // Lanes 0-3: pixels 0-3 of a row of the block; 4-7: of the row below.
    const __m256i ix = _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3);
    const __m256i iy = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1);
    const __m256d z0 = _mm256_set1_pd(static_cast<double>(t.z[0]));
    const __m256d gx = _mm256_set1_pd(dzdx), scale = _mm256_set1_pd(1.0 / kSubpixel);
    const __m256d column = _mm256_setr_pd(0.0, kSubpixel, 2.0 * kSubpixel, 3.0 * kSubpixel);
    const __m256 bias = _mm256_set1_ps(depth_bias), sign = _mm256_set1_ps(-0.0f);
    const __m256i dpass = _mm256_set1_epi32(delta_pass), dfail = _mm256_set1_epi32(delta_fail);
    const int64_t sx = static_cast<int64_t>(x0) * kSubpixel + sp.ox[0];
    const int64_t sy0 = static_cast<int64_t>(y0) * kSubpixel + sp.oy[0];
    // Each edge at the block's first sample of each lane, plus its fill-rule bias (an edge
    // left out of `crossing` is inside everywhere: zero, stepped by zero).
    __m256i w_rows[3], step[3], down[3];
    for (int k = 0; k < 3; ++k) {
        const bool used = (crossing >> k) & 1u;
        const int64_t a = used ? te.e[k].a * kSubpixel : 0;
        const int64_t b = used ? te.e[k].b * kSubpixel : 0;
        const int64_t e = used ? te.e[k].at(sx, sy0) + te.e[k].bias : 0;
        w_rows[k] = _mm256_add_epi32(
            _mm256_set1_epi32(static_cast<int32_t>(e)),
            _mm256_add_epi32(_mm256_mullo_epi32(ix, _mm256_set1_epi32(static_cast<int32_t>(a))),
                             _mm256_mullo_epi32(iy, _mm256_set1_epi32(static_cast<int32_t>(b)))));
        step[k] = _mm256_set1_epi32(static_cast<int32_t>(4 * a));
        down[k] = _mm256_set1_epi32(static_cast<int32_t>(2 * b));
    }
    for (int py = y0; py < y1; py += 2) {
        // (dzdy (y - y0) / 256 per row, the same for the row.)
        const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[0];
        const __m256d ty0 = _mm256_set1_pd(dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel);
        const __m256d ty1 =
            _mm256_set1_pd(dzdy * static_cast<double>(sy + kSubpixel - t.y[0]) / kSubpixel);
        const __m256i rows_in = _mm256_cmpgt_epi32(_mm256_set1_epi32(y1 - py), iy);
        const size_t row0 = static_cast<size_t>(py - tile.y0) * tw;
        const size_t row1 = py + 1 < y1 ? row0 + static_cast<size_t>(tw) : row0;
        __m256i w0 = w_rows[0], w1 = w_rows[1], w2 = w_rows[2];
        for (int px = x0; px < x1; px += 4) {
            const __m256i in =
                _mm256_and_si256(rows_in, _mm256_cmpgt_epi32(_mm256_set1_epi32(x1 - px), ix));
            const __m256i outside =
                _mm256_srai_epi32(_mm256_or_si256(_mm256_or_si256(w0, w1), w2), 31);
            const __m256i covered = _mm256_andnot_si256(outside, in);
            w0 = _mm256_add_epi32(w0, step[0]);
            w1 = _mm256_add_epi32(w1, step[1]);
            w2 = _mm256_add_epi32(w2, step[2]);
            if (_mm256_testz_si256(covered, covered)) continue;
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
        for (int k = 0; k < 3; ++k) w_rows[k] = _mm256_add_epi32(w_rows[k], down[k]);
    }
}

}  // namespace svetlo::raster

#pragma GCC pop_options
