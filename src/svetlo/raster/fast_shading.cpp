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

void shade_tile_fast(const FrameState& f, const Tile& tile, const SamplePattern& sp,
                     bool small_left_weights, TileBuffers& buf) {
    const int tw = tile.x1 - tile.x0, th = tile.y1 - tile.y0, S = sp.count;
    const size_t pixels = static_cast<size_t>(tw) * th;
    const Color background = f.scene->render.background, ambient = f.scene->render.ambient;
    EdgeCache edges(f);
    size_t count = pixels * static_cast<size_t>(S);
    const LightVisibility vis = light_visibility(buf, count);
    buf.sample_color.resize(count);
    ShadeBatch batch;
    const int batch_size = simd_lanes();
    size_t lane_of[ShadeBatch::kCapacity];
    Color lit[ShadeBatch::kCapacity];
    auto flush = [&] {
        shade_batch(batch, f.fast.lights, f.cam.eye, f.cam.orthographic, f.cam.forward, ambient,
                    lit, vis);
        for (int k = 0; k < batch.count; ++k) buf.sample_color[lane_of[k]] = lit[k];
        batch.count = 0;
    };
    // A textured triangle's uv gradients, made once for its samples.
    const SetupTriangle* gradients_of = nullptr;  // the triangle whose uv gradients these are
    UvGradients gradients;
    auto gradients_for = [&](const SetupTriangle& t) -> const UvGradients& {
        if (gradients_of != &t) {
            gradients_of = &t;
            gradients = uv_gradients(f, t, f.vertex(t.v[0]), f.vertex(t.v[1]), f.vertex(t.v[2]));
        }
        return gradients;
    };
    // A textured material's colours (ka, kd, ks) at a sample's uv and footprint.
    auto colours_at = [&](uint32_t material, const SurfaceUv& at, Color colours[3]) {
        Bsdf scratch;
        const Bsdf& bsdf = material_at(f, material, at, scratch);
        colours[0] = bsdf.ambient;
        colours[1] = bsdf.diffuse;
        colours[2] = bsdf.specular;
    };
    // The same at the `run` samples of a run, each colour's source evaluated for them all at
    // once (eval_colors), where the material's sources are known.
    auto colours_of_run = [&](uint32_t material, const SurfaceUv* at, int run, Color(*colours)[3]) {
        const FastShading::ColourSources& sources = f.fast.colour_sources[material];
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
        const TextureLookup lookup{f.scene->textures, f.mips};
        for (int slot = 0; slot < 3; ++slot) {
            const ColorSource* source = sources.of[slot];
            const bool same = slot > 0 && source == sources.of[slot - 1];
            if (source && !same)
                eval_colors(*source, uv, dx, dy, static_cast<size_t>(run), lookup, c);
            for (int k = 0; k < run; ++k)
                colours[k][slot] = !source ? Color(0.0f) : (same ? colours[k][slot - 1] : c[k]);
        }
    };
    // The same at a sample of triangle t with perspective weights w.
    auto textured_colours = [&](const SetupTriangle& t, const Weights& w, Color colours[3]) {
        colours_at(
            t.material,
            surface_uv(gradients_for(t), f.vertex(t.v[0]), f.vertex(t.v[1]), f.vertex(t.v[2]), w),
            colours);
    };
    // Gathers sample i of triangle t, at screen barycentrics l, into the batch.
    auto add_to_batch = [&](size_t i, vec2 l, const SetupTriangle& t) {
        const ClipVertex& A = f.vertex(t.v[0]);
        const ClipVertex& B = f.vertex(t.v[1]);
        const ClipVertex& C = f.vertex(t.v[2]);
        Weights w = perspective_weights(l, A, B, C);
        const bool textured = f.textured[t.material];
        Color colours[3];
        if (textured) textured_colours(t, w, colours);
        lane_of[batch.count] = i;
        batch.add(w.b[0] * A.world + w.b[1] * B.world + w.b[2] * C.world,
                  w.b[0] * A.normal + w.b[1] * B.normal + w.b[2] * C.normal, face_cross(t, A, B, C),
                  &f.fast.materials[t.material], static_cast<uint32_t>(i),
                  textured ? colours : nullptr);
        if (batch.count == batch_size) flush();
    };
    // A sample the batches do not take: the background, or a material off the
    // fast path (shaded alone). True when it is done.
    const ImageBasedLighting& ibl = f.lights->environment;
    const mat4 inverse = ibl.active() ? glm::inverse(f.cam.view_projection()) : mat4(1.0f);
    auto shade_apart = [&](size_t i, uint32_t tri, int64_t sx, int64_t sy) {
        if (tri == kNone) {  // the background, or the map along the sample's ray
            buf.sample_color[i] = ibl.active() ? ibl.seen(f.cam, inverse, sx, sy) : background;
            return true;
        }
        if (f.fast.material_ok[f.tri(tri).material]) return false;
        buf.sample_color[i] = shade_one(f, tri, edges, sx, sy, vis, i);
        return true;
    };
    // One sample per pixel: runs of one triangle along each row, their weights
    // stepped exactly (edge functions are affine), shaded four pixels at a time; a
    // textured material's colours are evaluated at each sample of the run first.
    Color run_colours[kTile][3];
    for (int row = 0; row < th && S == 1; ++row) {
        const size_t row_start = static_cast<size_t>(row) * tw;
        const int64_t sy = static_cast<int64_t>(tile.y0 + row) * kSubpixel + sp.oy[0];
        for (int px = 0; px < tw; ++px) {
            const size_t i = row_start + static_cast<size_t>(px);
            const int64_t sx = static_cast<int64_t>(tile.x0 + px) * kSubpixel + sp.ox[0];
            uint32_t tri = buf.tri[i];
            // The vertices of the triangle a few pixels on are fetched ahead:
            // a tile's vertices are scattered over the frame's.
            constexpr size_t kAhead = 8;
            if (i + kAhead < pixels) {
                uint32_t next = buf.tri[i + kAhead];
                if (next != kNone && next != tri) {
                    for (uint32_t v : f.tri(next).v)
                        _mm_prefetch(reinterpret_cast<const char*>(&f.vertex(v)), _MM_HINT_T0);
                }
            }
            if (shade_apart(i, tri, sx, sy)) continue;
            const SetupTriangle& t = f.tri(tri);
            if (small_left_weights && t.small) {
                // Short runs: straight into a batch, with the barycentrics
                // rasterize_small left.
                add_to_batch(i, vec2(buf.l1[i], buf.l2[i]), t);
                continue;
            }
            int end = px;
            while (end < tw && buf.tri[row_start + static_cast<size_t>(end)] == tri) ++end;
            // Groups of four along the run are shaded as spans; what is left
            // joins the batch, which gathers samples of small triangles.
            int spans_end = px + (end - px) / 4 * 4;
            if (spans_end > px) {
                const TriangleEdges& e = edges.of(tri);
                TriangleRun q;
                for (int v = 0; v < 3; ++v) {
                    q.invw[v] = f.vertex(t.v[v]).invw;
                    q.world[v] = f.vertex(t.v[v]).world;
                    q.normal[v] = f.vertex(t.v[v]).normal;
                }
                q.first_sample = static_cast<uint32_t>(i);
                if (f.textured[t.material]) {  // the colours at each sample of the spans
                    // Their uv and footprints lane by lane, then the lookups one by one.
                    const int spans = spans_end - px;
                    alignas(32) float l1[kTile], l2[kTile];
                    SurfaceUv at[kTile];
                    const ClipVertex& A = f.vertex(t.v[0]);
                    const ClipVertex& B = f.vertex(t.v[1]);
                    const ClipVertex& C = f.vertex(t.v[2]);
                    e.run_weights(sx, sy, spans, l1, l2);
                    surface_uvs(gradients_for(t), A, B, C, l1, l2, spans, at);
                    colours_of_run(t.material, at, spans, run_colours);
                    q.own = run_colours;
                }
                q.l1 = static_cast<float>(static_cast<double>(e.e[1].at(sx, sy)) * e.inv_area);
                q.l2 = static_cast<float>(static_cast<double>(e.e[2].at(sx, sy)) * e.inv_area);
                auto dl1 =
                    static_cast<float>(static_cast<double>(e.e[1].a * kSubpixel) * e.inv_area);
                auto dl2 =
                    static_cast<float>(static_cast<double>(e.e[2].a * kSubpixel) * e.inv_area);
                shade_run(q, dl1, dl2, (spans_end - px) / 4, f.fast.materials[t.material],
                          face_cross(t, f.vertex(t.v[0]), f.vertex(t.v[1]), f.vertex(t.v[2])),
                          f.fast.lights, f.cam.eye, f.cam.orthographic, f.cam.forward, ambient,
                          &buf.sample_color[i], 0, vis);
            }
            for (int x = spans_end; x < end; ++x) {
                add_to_batch(
                    row_start + static_cast<size_t>(x),
                    edges.of(tri).weights(sx + static_cast<int64_t>(x - px) * kSubpixel, sy), t);
            }
            px = end - 1;
        }
    }
    for (size_t i = 0; i < count && S > 1; ++i) {
        uint32_t tri = buf.tri[i];
        size_t pixel = i / static_cast<size_t>(S);
        int s = static_cast<int>(i % static_cast<size_t>(S));
        if (shade_apart(i, tri, sample_x(tile, pixel, sp, s), sample_y(tile, pixel, sp, s)))
            continue;
        const SetupTriangle& t = f.tri(tri);
        add_to_batch(
            i, edges.of(tri).weights(sample_x(tile, pixel, sp, s), sample_y(tile, pixel, sp, s)),
            t);
    }
    if (batch.count > 0) flush();
    // A sample that is not finite never reaches the pixel: dropped (black) and counted.
    for (size_t i = 0; i < count; ++i) {
        if (is_finite(buf.sample_color[i])) continue;
        buf.sample_color[i] = Color(0.0f);
        ++buf.nonfinite;
    }
}

}  // namespace svetlo::raster
