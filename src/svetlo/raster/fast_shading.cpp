// Stage 6's fast path: Lambert and Phong-family materials (their textured colours evaluated
// per sample, the runs' as the batches') under point, spot and directional lights and VPLs,
// lit eight (AVX2) or four samples at a time by simd_kernel.inc. Samples of other materials go
// through the scalar shading (fragment.cpp). With one sample per pixel, runs of one triangle along
// a row have their weights stepped exactly (edge functions are affine); small triangles' samples
// keep the barycentrics rasterize_small left.
#include <immintrin.h>

#include "svetlo/raster/fragment.h"
#include "svetlo/shading/texture.h"

namespace svetlo::raster {

namespace {

/// One tile's samples shaded by the fast path: what shade_tile_fast's steps share. Samples of
/// the fast path's materials gather in a batch, shaded when it is full (flush); runs of four
/// along a row are shaded as spans (shade_spans).
class FastTile {
public:
    FastTile(const FrameState& f, const Tile& tile, const SamplePattern& sp, TileBuffers& buf)
        : f_(f),
          tile_(tile),
          sp_(sp),
          buf_(buf),
          tw_(tile.x1 - tile.x0),
          th_(tile.y1 - tile.y0),
          S_(sp.count),
          pixels_(static_cast<size_t>(tw_) * th_),
          count_(pixels_ * static_cast<size_t>(S_)),
          background_(f.scene->render.background),
          ambient_(f.scene->render.ambient),
          edges_(f),
          vis_(light_visibility(buf, count_)),
          batch_size_(simd_lanes()),
          ibl_(f.lights->environment),
          rays_(f.cam) {
        buf_.sample_color.resize(count_);
    }

    /// One sample per pixel: runs of one triangle along each row, their weights stepped
    /// exactly (edge functions are affine), shaded four pixels at a time; a textured
    /// material's colours are evaluated at each sample of the run first. Small triangles'
    /// samples take the barycentrics rasterize_small left when `small_left_weights`.
    void shade_rows(bool small_left_weights);
    /// Several samples per pixel: each into the batch.
    void shade_samples();
    /// The last batch, and the samples that are not finite dropped (black) and counted.
    void finish();

private:
    void flush() {
        shade_batch(batch_, f_.fast.lights, f_.cam.eye, f_.cam.orthographic, f_.cam.forward,
                    ambient_, lit_, vis_);
        for (int k = 0; k < batch_.count; ++k) buf_.sample_color[lane_of_[k]] = lit_[k];
        batch_.count = 0;
    }
    /// The map behind the scene at the samples gathered, read many at a time.
    void flush_behind() {
        ibl_.environment().radiance_many(behind_dir_, static_cast<size_t>(behind_count_),
                                         behind_lit_);
        for (int k = 0; k < behind_count_; ++k) buf_.sample_color[behind_of_[k]] = behind_lit_[k];
        behind_count_ = 0;
    }
    /// A textured triangle's uv gradients, made once for its samples.
    const UvGradients& gradients_for(const SetupTriangle& t) {
        if (gradients_of_ != &t) {
            gradients_of_ = &t;
            gradients_ =
                uv_gradients(f_, t, f_.vertex(t.v[0]), f_.vertex(t.v[1]), f_.vertex(t.v[2]));
        }
        return gradients_;
    }
    /// A textured material's colours (ka, kd, ks) at a sample's uv and footprint.
    void colours_at(uint32_t material, const SurfaceUv& at, Color colours[3]) const {
        Bsdf scratch;
        const Bsdf& bsdf = material_at(f_, material, at, scratch);
        colours[0] = bsdf.ambient;
        colours[1] = bsdf.diffuse;
        colours[2] = bsdf.specular;
    }
    void colours_of_run(uint32_t material, const SurfaceUv* at, int run, Color (*colours)[3]) const;
    void add_to_batch(size_t i, vec2 l, const SetupTriangle& t);
    bool shade_apart(size_t i, uint32_t tri, int64_t sx, int64_t sy);
    void shade_spans(size_t i, uint32_t tri, const SetupTriangle& t, int64_t sx, int64_t sy,
                     int spans);

    const FrameState& f_;
    const Tile& tile_;
    const SamplePattern& sp_;
    TileBuffers& buf_;
    const int tw_, th_, S_;
    const size_t pixels_, count_;
    const Color background_, ambient_;
    EdgeCache edges_;
    const LightVisibility vis_;
    ShadeBatch batch_;
    const int batch_size_;
    size_t lane_of_[ShadeBatch::kCapacity];
    Color lit_[ShadeBatch::kCapacity];
    const SetupTriangle* gradients_of_ = nullptr;  // the triangle whose uv gradients these are
    UvGradients gradients_;
    const ImageBasedLighting& ibl_;
    const FilmRays rays_;  // the camera's rays, for the map behind
    static constexpr int kBehind = 64;
    int behind_count_ = 0;  // samples that see the map, waiting in behind_of_
    size_t behind_of_[kBehind];
    vec3 behind_dir_[kBehind];  // their rays' unit directions
    Color behind_lit_[kBehind];
    Color run_colours_[kTile][3];
};

/// The colours at the `run` samples of a run, each colour's source evaluated for them all at
/// once (eval_colors), where the material's sources are known.
void FastTile::colours_of_run(uint32_t material, const SurfaceUv* at, int run,
                              Color (*colours)[3]) const {
    const FastShading::ColourSources& sources = f_.fast.colour_sources[material];
    if (!sources.known) {
        for (int k = 0; k < run; ++k) colours_at(material, at[k], colours[k]);
        return;
    }
    vec2 uv[kTile], dx[kTile], dy[kTile];
    Color c[kTile];
    for (int k = 0; k < run; ++k) {
        uv[k] = at[k].uv;
        dx[k] = at[k].duv_dx;
        dy[k] = at[k].duv_dy;
    }
    const TextureLookup lookup{f_.scene->textures, f_.mips};
    for (int slot = 0; slot < 3; ++slot) {
        const ColorSource* source = sources.of[slot];
        const bool same = slot > 0 && source == sources.of[slot - 1];
        if (source && !same) eval_colors(*source, uv, dx, dy, static_cast<size_t>(run), lookup, c);
        for (int k = 0; k < run; ++k)
            colours[k][slot] = !source ? Color(0.0f) : (same ? colours[k][slot - 1] : c[k]);
    }
}

/// Gathers sample i of triangle t, at screen barycentrics l, into the batch.
inline void FastTile::add_to_batch(size_t i, vec2 l, const SetupTriangle& t) {
    const ClipVertex& A = f_.vertex(t.v[0]);
    const ClipVertex& B = f_.vertex(t.v[1]);
    const ClipVertex& C = f_.vertex(t.v[2]);
    Weights w = perspective_weights(l, A, B, C);
    const bool textured = f_.textured[t.material];
    Color colours[3];
    if (textured) colours_at(t.material, surface_uv(gradients_for(t), A, B, C, w), colours);
    lane_of_[batch_.count] = i;
    batch_.add(w.b[0] * A.world + w.b[1] * B.world + w.b[2] * C.world,
               w.b[0] * A.normal + w.b[1] * B.normal + w.b[2] * C.normal, face_cross(t, A, B, C),
               &f_.fast.materials[t.material], static_cast<uint32_t>(i),
               textured ? colours : nullptr);
    if (batch_.count == batch_size_) flush();
}

/// A sample the batches do not take: the background, or a material off the fast path (shaded
/// alone). True when it is done.
inline bool FastTile::shade_apart(size_t i, uint32_t tri, int64_t sx, int64_t sy) {
    if (tri == kNone) {  // the background, or the map along the sample's ray
        if (!ibl_.active()) {
            buf_.sample_color[i] = background_;
            return true;
        }
        behind_of_[behind_count_] = i;
        behind_dir_[behind_count_] = rays_.direction(sx, sy);
        if (++behind_count_ == kBehind) flush_behind();
        return true;
    }
    if (f_.fast.material_ok[f_.tri(tri).material]) return false;
    buf_.sample_color[i] = shade_one(f_, tri, edges_, sx, sy, vis_, i);
    return true;
}

/// `spans` groups of four samples of triangle t along a row from sample i, at (sx, sy).
void FastTile::shade_spans(size_t i, uint32_t tri, const SetupTriangle& t, int64_t sx, int64_t sy,
                           int spans) {
    const TriangleEdges& e = edges_.of(tri);
    TriangleRun q;
    for (int v = 0; v < 3; ++v) {
        q.invw[v] = f_.vertex(t.v[v]).invw;
        q.world[v] = f_.vertex(t.v[v]).world;
        q.normal[v] = f_.vertex(t.v[v]).normal;
    }
    q.first_sample = static_cast<uint32_t>(i);
    if (f_.textured[t.material]) {  // the colours at each sample of the spans
        // Their uv and footprints lane by lane, then the lookups one by one.
        const int samples = 4 * spans;
        alignas(32) float l1[kTile], l2[kTile];
        SurfaceUv at[kTile];
        e.run_weights(sx, sy, samples, l1, l2);
        surface_uvs(gradients_for(t), f_.vertex(t.v[0]), f_.vertex(t.v[1]), f_.vertex(t.v[2]), l1,
                    l2, samples, at);
        colours_of_run(t.material, at, samples, run_colours_);
        q.own = run_colours_;
    }
    q.l1 = static_cast<float>(static_cast<double>(e.e[1].at(sx, sy)) * e.inv_area);
    q.l2 = static_cast<float>(static_cast<double>(e.e[2].at(sx, sy)) * e.inv_area);
    auto dl1 = static_cast<float>(static_cast<double>(e.e[1].a * kSubpixel) * e.inv_area);
    auto dl2 = static_cast<float>(static_cast<double>(e.e[2].a * kSubpixel) * e.inv_area);
    shade_run(q, dl1, dl2, spans, f_.fast.materials[t.material],
              face_cross(t, f_.vertex(t.v[0]), f_.vertex(t.v[1]), f_.vertex(t.v[2])),
              f_.fast.lights, f_.cam.eye, f_.cam.orthographic, f_.cam.forward, ambient_,
              &buf_.sample_color[i], 0, vis_);
}

void FastTile::shade_rows(bool small_left_weights) {
    for (int row = 0; row < th_; ++row) {
        const size_t row_start = static_cast<size_t>(row) * tw_;
        const int64_t sy = static_cast<int64_t>(tile_.y0 + row) * kSubpixel + sp_.oy[0];
        for (int px = 0; px < tw_; ++px) {
            const size_t i = row_start + static_cast<size_t>(px);
            const int64_t sx = static_cast<int64_t>(tile_.x0 + px) * kSubpixel + sp_.ox[0];
            uint32_t tri = buf_.tri[i];
            // The vertices of the triangle a few pixels on are fetched ahead: a tile's
            // vertices are scattered over the frame's.
            constexpr size_t kAhead = 8;
            if (i + kAhead < pixels_) {
                uint32_t next = buf_.tri[i + kAhead];
                if (next != kNone && next != tri) {
                    for (uint32_t v : f_.tri(next).v)
                        _mm_prefetch(reinterpret_cast<const char*>(&f_.vertex(v)), _MM_HINT_T0);
                }
            }
            if (shade_apart(i, tri, sx, sy)) continue;
            const SetupTriangle& t = f_.tri(tri);
            if (small_left_weights && t.small) {
                // Short runs: straight into a batch, with the barycentrics rasterize_small
                // left.
                add_to_batch(i, vec2(buf_.l1[i], buf_.l2[i]), t);
                continue;
            }
            int end = px;
            while (end < tw_ && buf_.tri[row_start + static_cast<size_t>(end)] == tri) ++end;
            // Groups of four along the run are shaded as spans; what is left joins the batch,
            // which gathers samples of small triangles.
            int spans_end = px + (end - px) / 4 * 4;
            if (spans_end > px) shade_spans(i, tri, t, sx, sy, (spans_end - px) / 4);
            for (int x = spans_end; x < end; ++x) {
                add_to_batch(
                    row_start + static_cast<size_t>(x),
                    edges_.of(tri).weights(sx + static_cast<int64_t>(x - px) * kSubpixel, sy), t);
            }
            px = end - 1;
        }
    }
}

void FastTile::shade_samples() {
    for (size_t i = 0; i < count_; ++i) {
        uint32_t tri = buf_.tri[i];
        size_t pixel = i / static_cast<size_t>(S_);
        int s = static_cast<int>(i % static_cast<size_t>(S_));
        const int64_t sx = sample_x(tile_, pixel, sp_, s), sy = sample_y(tile_, pixel, sp_, s);
        if (shade_apart(i, tri, sx, sy)) continue;
        add_to_batch(i, edges_.of(tri).weights(sx, sy), f_.tri(tri));
    }
}

void FastTile::finish() {
    if (batch_.count > 0) flush();
    if (behind_count_ > 0) flush_behind();
    // A sample that is not finite never reaches the pixel: dropped (black) and counted.
    for (size_t i = 0; i < count_; ++i) {
        if (is_finite(buf_.sample_color[i])) continue;
        buf_.sample_color[i] = Color(0.0f);
        ++buf_.nonfinite;
    }
}

}  // namespace

void shade_tile_fast(const FrameState& f, const Tile& tile, const SamplePattern& sp,
                     bool small_left_weights, TileBuffers& buf) {
    FastTile shader(f, tile, sp, buf);
    if (sp.count == 1)
        shader.shade_rows(small_left_weights);
    else
        shader.shade_samples();
    shader.finish();
}

}  // namespace svetlo::raster
