// Stage 5 for passes with the stencil on or depth writes off (a shadow volume's passes, planar
// shadows' stencil): per sample, the stencil test and its operations around the depth test
// (stencil.h), and the depth written only where the state says so. test_samples below is the
// textbook loop; the rest are the shortcuts a shadow volume's count needs (its long sides, its
// small caps), each giving the counts of that loop (stencil_count.cpp counts).
#include <algorithm>
#include <cmath>

#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

namespace {

/// The textbook per-sample loop over the pixels r of the tile: coverage by the edge functions,
/// the stencil test and its fail operation, the depth test and its depth-fail operation, then
/// the pass operation, the depth (where the state writes it) and the triangle's id.
/// `all_fail`: the caller knows that every sample fails the depth test (none computed).
/// `alpha`, when given, is the pass's geometry for the alpha test (alpha_test.h): a sample
/// in a hole is not drawn, as if not covered.
void test_samples(uint32_t id, const SetupTriangle& t, const TriangleEdges& te, double dzdx,
                  double dzdy, PixelSpan r, const Tile& tile, const SamplePattern& sp,
                  const PipelineState& state, bool all_fail, TileBuffers& buf,
                  const PassGeometry* alpha = nullptr) {
    const StencilState& st = state.stencil;
    const StencilFace& face = t.front ? st.front : st.back;
    const int tw = tile.x1 - tile.x0, S = sp.count;
    for (int py = r.ys; py < r.ye; ++py) {
        for (int s = 0; s < S; ++s) {
            const int64_t sx = static_cast<int64_t>(r.xs) * kSubpixel + sp.ox[s];
            const int64_t sy = static_cast<int64_t>(py) * kSubpixel + sp.oy[s];
            int64_t w0 = te.e[0].at(sx, sy) + te.e[0].bias, w1 = te.e[1].at(sx, sy) + te.e[1].bias,
                    w2 = te.e[2].at(sx, sy) + te.e[2].bias;
            const int64_t d0 = te.e[0].a * kSubpixel, d1 = te.e[1].a * kSubpixel,
                          d2 = te.e[2].a * kSubpixel;
            size_t i = (static_cast<size_t>(py - tile.y0) * tw + (r.xs - tile.x0)) * S + s;
            for (int px = r.xs; px < r.xe; ++px, w0 += d0, w1 += d1, w2 += d2, i += S) {
                if ((w0 | w1 | w2) < 0) continue;
                if (alpha &&
                    in_alpha_hole(*alpha, id, t, te,
                                  static_cast<int64_t>(px) * kSubpixel + sp.ox[s], sy, state))
                    continue;
                uint8_t unused = 0;
                uint8_t& stencil = st.enabled ? buf.stencil[i] : unused;
                if (st.enabled && !stencil_test(face.func, st.ref, stencil, st.read_mask)) {
                    stencil = stencil_apply(face.fail, stencil, st.ref, st.write_mask);
                    continue;
                }
                if (all_fail) {
                    if (st.enabled)
                        stencil = stencil_apply(face.depth_fail, stencil, st.ref, st.write_mask);
                    continue;
                }
                const int64_t x = static_cast<int64_t>(px) * kSubpixel + sp.ox[s];
                auto z =
                    static_cast<float>(t.z[0] + dzdx * static_cast<double>(x - t.x[0]) / kSubpixel +
                                       dzdy * static_cast<double>(sy - t.y[0]) / kSubpixel);
                if (state.depth_test && !(z + state.depth_bias * std::abs(z) < buf.depth[i])) {
                    if (st.enabled)
                        stencil = stencil_apply(face.depth_fail, stencil, st.ref, st.write_mask);
                    continue;
                }
                if (st.enabled) stencil = stencil_apply(face.pass, stencil, st.ref, st.write_mask);
                if (state.depth_write) buf.depth[i] = z;
                buf.tri[i] = id;
            }
        }
    }
}

/// Every sample of the pixels r covered and failing the depth test, the stencil test Always:
/// the depth-fail operation on a run of bytes per row (a shadow volume's count behind the
/// scene, the common case).
void fail_all(const StencilState& st, const StencilFace& face, PixelSpan r, const Tile& tile,
              int samples, TileBuffers& buf) {
    const int tw = tile.x1 - tile.x0;
    for (int py = r.ys; py < r.ye; ++py) {
        uint8_t* row = buf.stencil.data() +
                       (static_cast<size_t>(py - tile.y0) * tw + (r.xs - tile.x0)) * samples;
        const size_t n = static_cast<size_t>(r.xe - r.xs) * samples;
        if (face.depth_fail == StencilOp::IncrWrap && st.write_mask == 0xff) {
            for (size_t k = 0; k < n; ++k) row[k] = static_cast<uint8_t>(row[k] + 1);
        } else if (face.depth_fail == StencilOp::DecrWrap && st.write_mask == 0xff) {
            for (size_t k = 0; k < n; ++k) row[k] = static_cast<uint8_t>(row[k] - 1);
        } else {
            for (size_t k = 0; k < n; ++k)
                row[k] = stencil_apply(face.depth_fail, row[k], st.ref, st.write_mask);
        }
    }
}

/// What the depth test does over a rectangle of pixels whose stored depths lie in
/// [near, far]: nothing to be done (every sample passes and passing does nothing, or fails and
/// failing does nothing), every sample fails, or either.
enum class DepthTest { Idle, AllFail, Either };

/// The edges over a rectangle: outside one at all four corners (nothing covered), the edges
/// with the rectangle on both sides, and the largest |edge function| that count_stencil's
/// four-wide steps can meet there.
struct EdgesOver {
    bool outside = false;
    unsigned crossing = 0;
    int64_t reach = 0;
};

/// The tests that let rasterize_stencil skip or shorten a rectangle of pixels (a block, a band
/// or the whole span), by the triangle's depth plane and edges at its corners.
struct RectTests {
    const SetupTriangle& t;
    const TriangleEdges& te;
    const PipelineState& state;
    double dzdx, dzdy;
    bool passing_is_idle, failing_is_idle;

    /// The depth plane at pixel position (px, py), in pixels.
    double plane(double px, double py) const {
        const double x0 = static_cast<double>(t.x[0]) / kSubpixel,
                     y0 = static_cast<double>(t.y[0]) / kSubpixel;
        return t.z[0] + dzdx * (px - x0) + dzdy * (py - y0);
    }

    DepthTest depth_over(PixelSpan r, float near, float far) const {
        const double c[4] = {plane(r.xs, r.ys), plane(r.xe, r.ys), plane(r.xs, r.ye),
                             plane(r.xe, r.ye)};
        auto zmax = static_cast<float>(std::max({c[0], c[1], c[2], c[3]}));
        auto zmin = static_cast<float>(std::min({c[0], c[1], c[2], c[3]}));
        // (z + bias |z| grows with z: the corners bound it too.)
        if (passing_is_idle && zmax + state.depth_bias * std::abs(zmax) < near)
            return DepthTest::Idle;
        if (zmin >= far) return failing_is_idle ? DepthTest::Idle : DepthTest::AllFail;
        return DepthTest::Either;
    }

    EdgesOver edges_over(PixelSpan r) const {
        const int64_t xa = static_cast<int64_t>(r.xs) * kSubpixel,
                      xb = static_cast<int64_t>(r.xe) * kSubpixel - 1;
        const int64_t ya = static_cast<int64_t>(r.ys) * kSubpixel,
                      yb = static_cast<int64_t>(r.ye) * kSubpixel - 1;
        EdgesOver out;
        for (int k = 0; k < 3; ++k) {
            const Edge& e = te.e[k];
            const int64_t c[4] = {e.at(xa, ya), e.at(xb, ya), e.at(xa, yb), e.at(xb, yb)};
            out.outside = out.outside || std::max({c[0], c[1], c[2], c[3]}) + e.bias < 0;
            if (std::min({c[0], c[1], c[2], c[3]}) + e.bias >= 0) continue;
            out.crossing |= 1u << k;
            for (int64_t v : c)
                out.reach = std::max(out.reach, std::abs(v) + 8 * std::abs(e.a) * kSubpixel + 1);
        }
        return out;
    }
};

/// The columns [x0, x1) of the rows [ry0, ry1) the triangle can reach: each edge bounds x on
/// one side over the rows' y range (a long, thin shadow-volume side crosses a tile's bounding
/// box on a few blocks of each row). A pixel of margin on each side covers the rounding.
std::pair<int, int> columns_reached(const TriangleEdges& te, int ry0, int ry1) {
    double left = -1e30, right = 1e30;
    for (int k = 0; k < 3; ++k) {
        const Edge& e = te.e[k];
        const double ya = static_cast<double>(ry0) * kSubpixel,
                     yb = static_cast<double>(ry1) * kSubpixel;
        const double ea = static_cast<double>(e.b) * ya + static_cast<double>(e.c + e.bias),
                     eb = static_cast<double>(e.b) * yb + static_cast<double>(e.c + e.bias);
        // E(x, y) = 0 at x = -E(0, y) / a, in pixels.
        const double to_x = e.a == 0 ? 0.0 : -1.0 / (static_cast<double>(e.a) * kSubpixel);
        if (e.a == 0) {
            if (std::max(ea, eb) < 0.0) right = -1e30;  // the whole row is outside
        } else if (e.a > 0) {  // inside where x >= -E(0, y) / a, for some y of the rows
            left = std::max(left, std::min(ea * to_x, eb * to_x));
        } else {  // inside where x <= -E(0, y) / a
            right = std::min(right, std::max(ea * to_x, eb * to_x));
        }
    }
    return {static_cast<int>(std::max(left - 1.0, -1e9)),
            static_cast<int>(std::min(right + 2.0, 1e9))};
}

/// rasterize_stencil counts a row of blocks as one band where a triangle reaches fewer blocks of
/// it than this.
constexpr int kBandBlocks = 3;

/// Stage 5 for one triangle over its span of the tile: test_samples over each 8 x 8 block it
/// covers, with two shortcuts per block, which shadow volumes' long sides need: a block no
/// edge lets in is skipped, and so is a block where every sample would pass the depth test and
/// passing changes nothing (no depth or item writes, the stencil's pass operation Keep): the
/// triangle's farthest depth over the block is nearer than the block's nearest stored depth
/// (TileBuffers::block_near, when a pass keeps it). And where the triangle's nearest depth over
/// the block is behind the block's farthest, every covered sample fails the depth test: the
/// block is skipped when failing does nothing (z-pass), else no depth is computed. A shadow
/// volume's count (one sample, the stencil test Always, adding and wrapping) goes to
/// count_stencil, by blocks, by bands of a row for thin triangles, or whole for small ones. The
/// blocks' deepest depths are left as they were (larger than the truth: safe).
void rasterize_stencil(uint32_t id, const SetupTriangle& t, const TriangleEdges& te, PixelSpan span,
                       const Tile& tile, const SamplePattern& sp, const PipelineState& state,
                       bool avx2, TileBuffers& buf) {
    const StencilState& st = state.stencil;
    const StencilFace& face = t.front ? st.front : st.back;
    double dzdx, dzdy;
    te.depth_gradient(t, dzdx, dzdy);
    const int S = sp.count, kB = TileBuffers::kBlock, bw = kTile / kB;
    const bool block_depths = state.depth_test && !state.depth_write && !buf.block_near.empty();
    const RectTests tests{
        t,
        te,
        state,
        dzdx,
        dzdy,
        block_depths && !state.write_items &&
            (!st.enabled || (face.pass == StencilOp::Keep && face.func == StencilFunc::Always)),
        block_depths && (!st.enabled ||
                         (face.depth_fail == StencilOp::Keep && face.func == StencilFunc::Always))};
    const StencilCount count{t,
                             te,
                             dzdx,
                             dzdy,
                             tile,
                             sp,
                             state.depth_bias,
                             stencil_delta(face.pass),
                             stencil_delta(face.depth_fail)};
    const bool counts_only = S == 1 && st.enabled && state.depth_test && !state.depth_write &&
                             !state.write_items && face.func == StencilFunc::Always &&
                             st.write_mask == 0xff && count.delta_pass != 2 &&
                             count.delta_fail != 2;
    if (counts_only && t.small) {
        // A small triangle (a cap of a shadow volume): its edge functions over its bounding
        // box fit in 32 bits; counted over the box at once, without the per-block tests,
        // which would cost more than they save.
        count_stencil(count, span, 7u, 0, false, avx2, buf);
        return;
    }
    // The same depth tests over the whole span first, against the tile's nearest and farthest
    // stored depths: a long side of a volume crosses many tiles wholly behind the scene.
    if (block_depths && tests.depth_over(span, buf.tile_near, buf.tile_far) == DepthTest::Idle)
        return;
    for (int by = (span.ys - tile.y0) / kB; by <= (span.ye - 1 - tile.y0) / kB; ++by) {
        const int ry0 = std::max(span.ys, tile.y0 + by * kB),
                  ry1 = std::min(span.ye, tile.y0 + (by + 1) * kB);
        const auto [left, right] = columns_reached(te, ry0, ry1);
        const int cx0 = std::max(span.xs, left), cx1 = std::min(span.xe, right);
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
            const PixelSpan band{cx0, cx1, ry0, ry1};
            const DepthTest test = tests.depth_over(band, near, far);
            if (test == DepthTest::Idle) continue;
            const EdgesOver edges = tests.edges_over(band);
            if (!edges.outside)
                count_stencil(count, band, edges.crossing, edges.reach, test == DepthTest::AllFail,
                              avx2, buf);
            continue;
        }
        for (int bx = bx0; bx <= bx1; ++bx) {
            const PixelSpan block{std::max(span.xs, tile.x0 + bx * kB),
                                  std::min(span.xe, tile.x0 + (bx + 1) * kB), ry0, ry1};
            bool all_fail = false;
            if (block_depths) {
                const size_t b = static_cast<size_t>(by) * bw + bx;
                const DepthTest test = tests.depth_over(block, buf.block_near[b], buf.block_far[b]);
                if (test == DepthTest::Idle) continue;
                all_fail = test == DepthTest::AllFail;
            }
            const EdgesOver edges = tests.edges_over(block);
            if (edges.outside) continue;
            if (all_fail && edges.crossing == 0 && st.enabled && face.func == StencilFunc::Always) {
                fail_all(st, face, block, tile, S, buf);
            } else if (counts_only) {
                count_stencil(count, block, edges.crossing, edges.reach, all_fail, avx2, buf);
            } else {
                test_samples(id, t, te, dzdx, dzdy, block, tile, sp, state, all_fail, buf);
            }
        }
    }
}

}  // namespace

void rasterize_tile_stencil(const PassGeometry& f, const Tile& tile, const SamplePattern& sp,
                            const PipelineState& state, TileBuffers& buf) {
    for_each_binned(f, tile, [&](uint32_t id, const SetupTriangle& t) {
        const PixelSpan span = span_in(t, tile);
        if (span.empty()) return;
        if (state.alpha && state.alpha->active(t.material)) {  // sample by sample
            const TriangleEdges te(t);
            double dzdx, dzdy;
            te.depth_gradient(t, dzdx, dzdy);
            test_samples(id, t, te, dzdx, dzdy, span, tile, sp, state, false, buf, &f);
            return;
        }
        rasterize_stencil(id, t, TriangleEdges(t), span, tile, sp, state, f.avx2, buf);
    });
}

}  // namespace svetlo::raster
