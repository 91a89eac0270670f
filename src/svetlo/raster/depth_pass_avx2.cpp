// A depth-only pass with AVX2 (pipeline.h): its setup eight triangles at a time
// (setup_depth_avx2: setup_triangle's bounds, facing and culling, for the triangles that take
// the fast road, small with all three vertices inside the clip volume; the others are handed
// back), and its records drawn 4 x 2 pixels at a time (rasterize_depth_avx2: the same depths
// as rasterize_small draws from a SetupTriangle, bit for bit). Used only where
// avx2_available(). The target is set by pragma after the headers, as in simd_shading_avx2.cpp.
#include <immintrin.h>

#include <algorithm>

#include "svetlo/raster/pipeline.h"

#pragma GCC push_options
#pragma GCC target("avx2,bmi")

namespace svetlo::raster {

namespace {

/// Rows r0..r3 of four 32-bit lanes (twice: the low and high halves of each register, a
/// vertex of triangles 0-3 and 4-7) into columns: out[k] holds field k of the eight.
void transpose4(const __m256i in[4], __m256i out[4]) {
    const __m256i t0 = _mm256_unpacklo_epi32(in[0], in[1]),
                  t1 = _mm256_unpackhi_epi32(in[0], in[1]);
    const __m256i t2 = _mm256_unpacklo_epi32(in[2], in[3]),
                  t3 = _mm256_unpackhi_epi32(in[2], in[3]);
    out[0] = _mm256_unpacklo_epi64(t0, t2);
    out[1] = _mm256_unpackhi_epi64(t0, t2);
    out[2] = _mm256_unpacklo_epi64(t1, t3);
    out[3] = _mm256_unpackhi_epi64(t1, t3);
}

/// Eight columns of eight 32-bit lanes into eight rows (row k: lane k of every column).
void transpose8(const __m256i in[8], __m256i out[8]) {
    __m256 a[8], b[8];
    for (int k = 0; k < 8; k += 2) {
        a[k] = _mm256_castsi256_ps(_mm256_unpacklo_epi32(in[k], in[k + 1]));
        a[k + 1] = _mm256_castsi256_ps(_mm256_unpackhi_epi32(in[k], in[k + 1]));
    }
    for (int k = 0; k < 8; k += 4) {
        b[k] = _mm256_shuffle_ps(a[k], a[k + 2], _MM_SHUFFLE(1, 0, 1, 0));
        b[k + 1] = _mm256_shuffle_ps(a[k], a[k + 2], _MM_SHUFFLE(3, 2, 3, 2));
        b[k + 2] = _mm256_shuffle_ps(a[k + 1], a[k + 3], _MM_SHUFFLE(1, 0, 1, 0));
        b[k + 3] = _mm256_shuffle_ps(a[k + 1], a[k + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
    for (int k = 0; k < 4; ++k) {
        out[k] = _mm256_castps_si256(_mm256_permute2f128_ps(b[k], b[k + 4], 0x20));
        out[k + 4] = _mm256_castps_si256(_mm256_permute2f128_ps(b[k], b[k + 4], 0x31));
    }
}

/// The gradients of depth_plane (small_triangle.h) for four lanes, in the same operations.
void gradients4(__m128i rx0, __m128i rx1, __m128i rx2, __m128i ry0, __m128i ry1, __m128i ry2,
                __m128 dz1, __m128 dz2, __m128 inv_area, __m128& out_dzdx, __m128& out_dzdy) {
    const __m256d per_pixel =
        _mm256_mul_pd(_mm256_set1_pd(static_cast<double>(kSubpixel)), _mm256_cvtps_pd(inv_area));
    const __m256d z1 = _mm256_cvtps_pd(dz1), z2 = _mm256_cvtps_pd(dz2);
    const __m256d dzdx =
        _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_cvtepi32_pd(_mm_sub_epi32(ry2, ry0)), z1),
                                    _mm256_mul_pd(_mm256_cvtepi32_pd(_mm_sub_epi32(ry0, ry1)), z2)),
                      per_pixel);
    const __m256d dzdy =
        _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_cvtepi32_pd(_mm_sub_epi32(rx0, rx2)), z1),
                                    _mm256_mul_pd(_mm256_cvtepi32_pd(_mm_sub_epi32(rx1, rx0)), z2)),
                      per_pixel);
    out_dzdx = _mm256_cvtpd_ps(dzdx);
    out_dzdy = _mm256_cvtpd_ps(dzdy);
}

/// Half h (0: lanes 0-3, 1: lanes 4-7) of an eight-lane register.
__m128i half(__m256i v, int h) {
    return h == 0 ? _mm256_castsi256_si128(v) : _mm256_extracti128_si256(v, 1);
}
__m128 half(__m256 v, int h) {
    return h == 0 ? _mm256_castps256_ps128(v) : _mm256_extractf128_ps(v, 1);
}
__m256i join(__m128 lo, __m128 hi) { return _mm256_castps_si256(_mm256_set_m128(hi, lo)); }

/// Two 16-bit fields in one 32-bit lane: lo in the low half (as stored little-endian).
__m256i lo16_hi16(__m256i lo, __m256i hi) {
    return _mm256_or_si256(_mm256_and_si256(lo, _mm256_set1_epi32(0xffff)),
                           _mm256_slli_epi32(hi, 16));
}

/// Eight 16-bit lanes of bytes: pshufb's control taking 16-bit lanes l[0..7] of a register.
__m128i words(int l0, int l1, int l2, int l3, int l4, int l5, int l6, int l7) {
    const int l[8] = {l0, l1, l2, l3, l4, l5, l6, l7};
    alignas(16) int8_t b[16];
    for (int k = 0; k < 8; ++k) {
        b[2 * k] = static_cast<int8_t>(2 * l[k]);
        b[2 * k + 1] = static_cast<int8_t>(2 * l[k] + 1);
    }
    return _mm_load_si128(reinterpret_cast<const __m128i*>(b));
}

/// The screen vertices of eight triangles (24 indices, three to a triangle), transposed: per
/// corner c, the eight triangles' x, y, depth key and inside flag.
[[gnu::always_inline]] inline void load8(const ScreenVertex* screen, const uint32_t* indices,
                                         __m256i X[3], __m256i Y[3], __m256 Z[3], __m256i IN[3]) {
    for (int c = 0; c < 3; ++c) {
        __m256i rows[4], cols[4];
        for (int k = 0; k < 4; ++k) {
            rows[k] = _mm256_loadu2_m128i(
                reinterpret_cast<const __m128i*>(&screen[indices[3 * (k + 4) + c]]),
                reinterpret_cast<const __m128i*>(&screen[indices[3 * k + c]]));
        }
        transpose4(rows, cols);
        X[c] = cols[0];
        Y[c] = cols[1];
        Z[c] = _mm256_castsi256_ps(cols[2]);
        IN[c] = cols[3];
    }
}

/// The eight triangles' DepthTriangle records from their corners, signed areas, facing and
/// pixel bounds [x0, x1) x [y0, y1), stored from out[n] on; `n` moves on for the lanes of
/// fast_bits only. Returns it.
[[gnu::always_inline]] inline size_t write_records(const __m256i X[3], const __m256i Y[3],
                                                   const __m256 Z[3], __m256i area, __m256i front,
                                                   __m256i x0, __m256i y0, __m256i x1, __m256i y1,
                                                   glm::ivec2 lo, unsigned fast_bits,
                                                   DepthTriangle* out, size_t n) {
    // Wound so that the area is positive: vertices 1 and 2 swapped where it is negative.
    const __m256i X1 = _mm256_blendv_epi8(X[1], X[2], front),
                  X2 = _mm256_blendv_epi8(X[2], X[1], front);
    const __m256i Y1 = _mm256_blendv_epi8(Y[1], Y[2], front),
                  Y2 = _mm256_blendv_epi8(Y[2], Y[1], front);
    const __m256 fz = _mm256_castsi256_ps(front);
    const __m256 Z1 = _mm256_blendv_ps(Z[1], Z[2], fz), Z2 = _mm256_blendv_ps(Z[2], Z[1], fz);
    // Relative to the sample of the corner pixel (DepthTriangle; a depth-only pass's one
    // sample is at sample_bounds.lo).
    const __m256i lo_x = _mm256_set1_epi32(lo.x), lo_y = _mm256_set1_epi32(lo.y);
    const __m256i sx = _mm256_add_epi32(_mm256_slli_epi32(x0, kSubpixelBits), lo_x);
    const __m256i sy = _mm256_add_epi32(_mm256_slli_epi32(y0, kSubpixelBits), lo_y);
    const __m256i rx0 = _mm256_sub_epi32(X[0], sx), rx1 = _mm256_sub_epi32(X1, sx),
                  rx2 = _mm256_sub_epi32(X2, sx);
    const __m256i ry0 = _mm256_sub_epi32(Y[0], sy), ry1 = _mm256_sub_epi32(Y1, sy),
                  ry2 = _mm256_sub_epi32(Y2, sy);
    const __m256 inv_area =
        _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_cvtepi32_ps(_mm256_abs_epi32(area)));
    const __m256 dz1 = _mm256_sub_ps(Z1, Z[0]), dz2 = _mm256_sub_ps(Z2, Z[0]);
    __m128 dzdx[2], dzdy[2];
    for (int h = 0; h < 2; ++h) {
        gradients4(half(rx0, h), half(rx1, h), half(rx2, h), half(ry0, h), half(ry1, h),
                   half(ry2, h), half(dz1, h), half(dz2, h), half(inv_area, h), dzdx[h], dzdy[h]);
    }
    const __m256i cols[8] = {lo16_hi16(x0, y0),
                             lo16_hi16(_mm256_sub_epi32(x1, _mm256_set1_epi32(1)),
                                       _mm256_sub_epi32(y1, _mm256_set1_epi32(1))),
                             lo16_hi16(rx0, rx1),
                             lo16_hi16(rx2, ry0),
                             lo16_hi16(ry1, ry2),
                             _mm256_castps_si256(Z[0]),
                             join(dzdx[0], dzdx[1]),
                             join(dzdy[0], dzdy[1])};
    __m256i rows[8];
    transpose8(cols, rows);
    // Every lane stored, the next record's place moved on for the fast ones only: the
    // others are overwritten (a place within the chunk's: n <= t + k).
    for (int k = 0; k < 8; ++k) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + n), rows[k]);
        n += (fast_bits >> k) & 1u;
    }
    return n;
}

}  // namespace

size_t setup_depth_avx2(const PassGeometry& f, const uint32_t* indices, size_t count,
                        DepthTriangle* out, uint32_t* others, size_t& other_count) {
    static_assert(sizeof(ScreenVertex) == 16);
    const auto& b = f.sample_bounds;
    const __m256i zero = _mm256_setzero_si256();
    const __m256i small_side = _mm256_set1_epi32(kSmall * kSubpixel + 1);
    const __m256i hi_x = _mm256_set1_epi32(b.hi.x), hi_y = _mm256_set1_epi32(b.hi.y);
    const __m256i lo_x = _mm256_set1_epi32(b.lo.x), lo_y = _mm256_set1_epi32(b.lo.y);
    const __m256i margin = _mm256_set1_epi32(b.margin);
    const __m256i margin1 = _mm256_set1_epi32(b.margin + 1);
    const __m256i width = _mm256_set1_epi32(f.cam.width), height = _mm256_set1_epi32(f.cam.height);
    const ScreenVertex* screen = f.screen.data();
    size_t n = 0;
    for (size_t t = 0; t + 8 <= count; t += 8, indices += 24) {
        // The three vertices' fields, eight triangles to a register.
        __m256i X[3], Y[3], IN[3];
        __m256 Z[3];
        load8(screen, indices, X, Y, Z, IN);
        const __m256i inside =
            _mm256_cmpgt_epi32(_mm256_and_si256(_mm256_and_si256(IN[0], IN[1]), IN[2]), zero);
        const __m256i xmin = _mm256_min_epi32(X[0], _mm256_min_epi32(X[1], X[2]));
        const __m256i xmax = _mm256_max_epi32(X[0], _mm256_max_epi32(X[1], X[2]));
        const __m256i ymin = _mm256_min_epi32(Y[0], _mm256_min_epi32(Y[1], Y[2]));
        const __m256i ymax = _mm256_max_epi32(Y[0], _mm256_max_epi32(Y[1], Y[2]));
        const __m256i small =
            _mm256_and_si256(_mm256_cmpgt_epi32(small_side, _mm256_sub_epi32(xmax, xmin)),
                             _mm256_cmpgt_epi32(small_side, _mm256_sub_epi32(ymax, ymin)));
        // Twice the signed area (signed_area2): exact in 32 bits for a small triangle.
        const __m256i area = _mm256_sub_epi32(
            _mm256_mullo_epi32(_mm256_sub_epi32(X[1], X[0]), _mm256_sub_epi32(Y[2], Y[0])),
            _mm256_mullo_epi32(_mm256_sub_epi32(X[2], X[0]), _mm256_sub_epi32(Y[1], Y[0])));
        const __m256i front = _mm256_cmpgt_epi32(zero, area);  // front_facing
        __m256i keep = _mm256_xor_si256(_mm256_cmpeq_epi32(area, zero), _mm256_set1_epi32(-1));
        if (f.cull == CullMode::Back) keep = _mm256_and_si256(keep, front);
        if (f.cull == CullMode::Front) keep = _mm256_andnot_si256(front, keep);
        // The bounds (setup_triangle's rule).
        const __m256i x0 = _mm256_max_epi32(
            zero, _mm256_sub_epi32(
                      _mm256_sub_epi32(zero, _mm256_srai_epi32(_mm256_sub_epi32(hi_x, xmin), 8)),
                      margin));
        const __m256i y0 = _mm256_max_epi32(
            zero, _mm256_sub_epi32(
                      _mm256_sub_epi32(zero, _mm256_srai_epi32(_mm256_sub_epi32(hi_y, ymin), 8)),
                      margin));
        const __m256i x1 = _mm256_min_epi32(
            width, _mm256_add_epi32(_mm256_srai_epi32(_mm256_sub_epi32(xmax, lo_x), 8), margin1));
        const __m256i y1 = _mm256_min_epi32(
            height, _mm256_add_epi32(_mm256_srai_epi32(_mm256_sub_epi32(ymax, lo_y), 8), margin1));
        const __m256i some =
            _mm256_and_si256(_mm256_cmpgt_epi32(x1, x0), _mm256_cmpgt_epi32(y1, y0));
        const __m256i fast =
            _mm256_and_si256(_mm256_and_si256(inside, small), _mm256_and_si256(keep, some));
        // The rest of the inside ones are dropped unless they are not small; the outside ones
        // are clipped: both by the caller.
        const __m256i other =
            _mm256_andnot_si256(_mm256_and_si256(inside, small), _mm256_set1_epi32(-1));
        for (unsigned m = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(other)));
             m != 0; m &= m - 1)
            others[other_count++] = static_cast<uint32_t>(t) + static_cast<uint32_t>(_tzcnt_u32(m));
        const unsigned fast_bits =
            static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(fast)));
        if (fast_bits == 0) continue;
        n = write_records(X, Y, Z, area, front, x0, y0, x1, y1, b.lo, fast_bits, out, n);
    }
    return n;
}

void rasterize_depth_avx2(const PassGeometry& f, const Tile& tile, TileBuffers& buf) {
    // The record's rx[0..2], ry[0..2] as 16-bit lanes 0-5 of a load from rx (lanes 6-7: the
    // plane's first float, unused). Edge k runs from vertex i = k + 1 to j = k + 2: in 32-bit
    // lane k, the pairs (rx_i, ry_i) and (rx_j, ry_j) (lane 3 repeats lane 2, unused).
    const __m128i take_i = words(1, 4, 2, 5, 0, 3, 0, 3), take_j = words(2, 5, 0, 3, 1, 4, 1, 4);
    const __m128i swap = words(1, 0, 3, 2, 5, 4, 7, 6), minus_plus = _mm_set1_epi32(0x0001ffff);
    // The 4 x 2 block: lanes 0-3 pixels 0-3 of its first row, 4-7 of its second; as pairs of
    // 16-bit fixed-point offsets (x 256 in the low half, y 256 in the high half) for madd.
    const __m256i ix = _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3);
    const __m256i iy = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1);
    const __m256 ixf = _mm256_cvtepi32_ps(ix), iyf = _mm256_cvtepi32_ps(iy);
    const __m256i lane_offsets = _mm256_or_si256(_mm256_slli_epi32(ix, kSubpixelBits),
                                                 _mm256_slli_epi32(iy, 16 + kSubpixelBits));
    const int tw = tile.x1 - tile.x0;
    const size_t ti = static_cast<size_t>(tile.y0 / kTile) * f.tiles_x + tile.x0 / kTile;
    for_each_in_bins(
        f.depth_bins, ti, [&](uint32_t id) -> const DepthTriangle& { return f.depth_tris[id]; },
        [&](uint32_t, const DepthTriangle& d) {
            const int xs = std::max<int>(d.bx0, tile.x0), xe = std::min(d.bx1 + 1, tile.x1);
            const int ys = std::max<int>(d.by0, tile.y0), ye = std::min(d.by1 + 1, tile.y1);
            if (xs >= xe || ys >= ye) return;
            // small_edges, three edges at once: D = (dx, dy) = vertex j - vertex i, Q = (-dy,
            // dx) = (step_x, step_y) / 256, E at the corner = dy rx_i - dx ry_i = -Q . R_i.
            const __m128i r = _mm_loadu_si128(reinterpret_cast<const __m128i*>(d.rx));
            const __m128i ri = _mm_shuffle_epi8(r, take_i), rj = _mm_shuffle_epi8(r, take_j);
            const __m128i q =
                _mm_sign_epi16(_mm_shuffle_epi8(_mm_sub_epi16(rj, ri), swap), minus_plus);
            const __m128i w = _mm_sub_epi32(_mm_setzero_si128(), _mm_madd_epi16(q, ri));
            // top_left(a, b) with a = -dy (low half), b = dx (high half); bias -1 where not.
            const __m128i gt = _mm_cmpgt_epi16(q, _mm_setzero_si128());
            const __m128i eq = _mm_cmpeq_epi16(q, _mm_setzero_si128());
            const __m128i tl = _mm_or_si128(gt, _mm_and_si128(eq, _mm_srli_epi32(gt, 16)));
            const __m128i not_tl =
                _mm_xor_si128(_mm_srai_epi32(_mm_slli_epi32(tl, 16), 16), _mm_set1_epi32(-1));
            const __m128i wb = _mm_add_epi32(w, not_tl);
            const __m256i w0 = _mm256_broadcastd_epi32(wb),
                          w1 = _mm256_broadcastd_epi32(_mm_shuffle_epi32(wb, 1)),
                          w2 = _mm256_broadcastd_epi32(_mm_shuffle_epi32(wb, 2));
            const __m256i q0 = _mm256_broadcastd_epi32(q),
                          q1 = _mm256_broadcastd_epi32(_mm_shuffle_epi32(q, 1)),
                          q2 = _mm256_broadcastd_epi32(_mm_shuffle_epi32(q, 2));
            // Depth as rasterize_small: from the span's first sample (depth_at), dzdy per row
            // and dzdx per pixel, each rounded in float.
            const __m256 z_origin = _mm256_set1_ps(depth_at(
                d.plane, (xs - d.bx0) * kSubpixel - d.rx[0], (ys - d.by0) * kSubpixel - d.ry[0]));
            const __m256 dzdy = _mm256_set1_ps(d.plane.dzdy);
            const __m256 z_steps = _mm256_mul_ps(_mm256_set1_ps(d.plane.dzdx), ixf);
            const __m256 dzdx4 = _mm256_set1_ps(4.0f * d.plane.dzdx);
            for (int py = ys; py < ye; py += 2) {
                const int j = py - d.by0;
                const __m256 z_row = _mm256_add_ps(
                    z_origin,
                    _mm256_mul_ps(dzdy,
                                  _mm256_add_ps(_mm256_set1_ps(static_cast<float>(py - ys)), iyf)));
                const __m256i rows_in = _mm256_cmpgt_epi32(_mm256_set1_epi32(ye - py), iy);
                float* row0 = &buf.depth[static_cast<size_t>(py - tile.y0) * tw];
                float* row1 = py + 1 < ye ? row0 + tw : row0;
                __m256 z = _mm256_add_ps(z_row, z_steps);
                for (int px = xs; px < xe; px += 4, z = _mm256_add_ps(z, dzdx4)) {
                    const int i = px - d.bx0;
                    const __m256i p = _mm256_add_epi32(
                        lane_offsets,
                        _mm256_set1_epi32((i << kSubpixelBits) | (j << (16 + kSubpixelBits))));
                    const __m256i e0 = _mm256_add_epi32(w0, _mm256_madd_epi16(q0, p));
                    const __m256i e1 = _mm256_add_epi32(w1, _mm256_madd_epi16(q1, p));
                    const __m256i e2 = _mm256_add_epi32(w2, _mm256_madd_epi16(q2, p));
                    const __m256i in = _mm256_and_si256(
                        rows_in, _mm256_cmpgt_epi32(_mm256_set1_epi32(xe - px), ix));
                    const __m256 covered = _mm256_castsi256_ps(_mm256_andnot_si256(
                        _mm256_srai_epi32(_mm256_or_si256(_mm256_or_si256(e0, e1), e2), 31), in));
                    float* at0 = row0 + (px - tile.x0);
                    float* at1 = row1 + (px - tile.x0);
                    const __m256 old = _mm256_loadu2_m128(at1, at0);
                    const __m256 pass = _mm256_and_ps(covered, _mm256_cmp_ps(z, old, _CMP_LT_OQ));
                    const __m256 out = _mm256_blendv_ps(old, z, pass);
                    // The second row first: where there is none it is the first, unchanged.
                    _mm_storeu_ps(at1, _mm256_extractf128_ps(out, 1));
                    _mm_storeu_ps(at0, _mm256_castps256_ps128(out));
                }
            }
        });
}

}  // namespace svetlo::raster

#pragma GCC pop_options
