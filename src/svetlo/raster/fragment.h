// Stage 6: the colour of the visible samples, by shading mode: flat (one colour per face,
// lit at its centroid), Gouraud (vertex colours, interpolated), Phong (normals interpolated,
// lit per sample), the depth and normal views, the overdraw count; perspective-correct
// interpolation of every attribute; textures filtered with the pixel's footprint. The
// lighting is shading/'s (shade_point in raster_lights.h); the SIMD fast path
// (fast_shading.cpp) computes the same for the commonest materials.
#pragma once

#include "svetlo/raster/pipeline.h"
#include "svetlo/scene/renderer.h"

namespace svetlo::raster {

/// The material's BRDF at a point: the per-material constant one, or (in `scratch`) textures
/// evaluated with the footprint when the rasterizer has one.
struct SurfaceUv;
const Bsdf& material_at(const FrameShading& f, uint32_t m, const SurfaceUv& at, Bsdf& scratch);

/// The same for lighting a vertex or a face in flat and Gouraud shading: with the base colour's
/// texture made white, when the fragments modulate by it (FrameShading::modulate).
const Bsdf& material_for_vertices(const FrameShading& f, uint32_t m, const Varyings& at,
                                  Bsdf& scratch);

/// Lit colour at a point with unit geometric normal ng (the counter-clockwise side) and
/// shading normal ns (unit or zero), seen from the camera along -wo (shading_frame.h).
/// Each light's term is multiplied by its visibility at `sample` of the tile.
Color light_point(const FrameShading& f, const Bsdf& bsdf, vec3 p, vec3 wo, vec3 ng, vec3 ns,
                  const LightVisibility& vis = {}, size_t sample = 0);

/// Flat shading: one normal and one colour per face, lit at the centroid of the triangle of
/// vertices `idx` (in the vertex stage's output). With f.per_light, emission and ambient only,
/// and each light's term into `per_light` (f.sources of them).
Color flat_colour(const FrameState& f, const uint32_t idx[3], uint32_t material,
                  Color* per_light = nullptr);

/// Emission and ambient at a point, and each light's term alone into per_light[0, f.sources)
/// (flat and Gouraud shading under a shadow technique).
Color light_point_per_light(const FrameShading& f, const Bsdf& bsdf, vec3 p, vec3 wo, vec3 ng,
                            vec3 ns, Color* per_light);

/// Perspective-correct weights of a sample: the screen barycentrics over w (q), and
/// renormalised (b): b interpolates any attribute of the vertices.
struct Weights {
    float q[3], b[3];
};
inline Weights perspective_weights(vec2 l, const ClipVertex& A, const ClipVertex& B,
                                   const ClipVertex& C) {
    Weights w;
    w.q[0] = (1.0f - l.x - l.y) * A.invw;
    w.q[1] = l.x * B.invw;
    w.q[2] = l.y * C.invw;
    float inv_q = 1.0f / (w.q[0] + w.q[1] + w.q[2]);
    for (int k = 0; k < 3; ++k) w.b[k] = w.q[k] * inv_q;
    return w;
}

/// A sample's varyings (texture coordinates of both sets, vertex colour) and, for the
/// materials whose filters need the pixel's footprint (FrameShading::needs_footprint), each
/// set's d(uv)/dx and d(uv)/dy (else zero), from its perspective weights w in triangle t of
/// vertices A, B, C.
struct SurfaceUv {
    vec2 uv{0.0f}, duv_dx{0.0f}, duv_dy{0.0f};
    vec2 uv1{0.0f}, duv1_dx{0.0f}, duv1_dy{0.0f};
    vec4 color{1.0f};

    Varyings varyings() const { return {uv, uv1, color}; }
    TextureLookup lookup(const FrameShading& f) const {
        return {f.scene->textures, f.mips, duv_dx, duv_dy, duv1_dx, duv1_dy};
    }
};
SurfaceUv surface_uv(const FrameState& f, const SetupTriangle& t, const ClipVertex& A,
                     const ClipVertex& B, const ClipVertex& C, const Weights& w);

/// What surface_uv's footprint takes from the triangle alone, made once for the samples of
/// one triangle: per screen axis, the derivatives dq_i of the perspective weights' numerators
/// (the screen barycentrics' gradient a / area per pixel, times 1/w_i) and their sum.
struct UvGradients {
    bool footprint = false;  // FrameShading::needs_footprint of its material
    float dq[2][3]{}, dsum[2]{};
};
UvGradients uv_gradients(const FrameState& f, const SetupTriangle& t, const ClipVertex& A,
                         const ClipVertex& B, const ClipVertex& C);
/// surface_uv from the triangle's gradients (the same numbers, bit for bit).
SurfaceUv surface_uv(const UvGradients& g, const ClipVertex& A, const ClipVertex& B,
                     const ClipVertex& C, const Weights& w);
/// surface_uv's set 0 at n samples of one triangle (n <= kTile) with screen barycentrics
/// (l1[k], l2[k]) of vertices 1 and 2, lane by lane (the same numbers), into out[k]: for the
/// fast path, whose materials read no other varying (uv1 and color are left as made).
void surface_uvs(const UvGradients& g, const ClipVertex& A, const ClipVertex& B,
                 const ClipVertex& C, const float* l1, const float* l2, int n, SurfaceUv* out);

/// Stage 6 for the samples the fast path does not take, and for every mode but the fast
/// Phong path: shades the tile's visible samples and adds them (per pixel) into buf.color
/// and, when `aovs`, buf.aov; MSAA shades once per pixel and triangle.
void shade_tile(const FrameState& f, const Tile& tile, const SamplePattern& sp, bool msaa,
                bool aovs, TileBuffers& buf);

/// One visible sample alone: its colour (for the fast path's exceptions).
Color shade_one(const FrameState& f, uint32_t tri, EdgeCache& edges, int64_t sx, int64_t sy,
                const LightVisibility& vis, size_t sample);

/// Stage 6's fast path (fast_shading.cpp): constant Lambert and Phong-family materials under
/// point, spot and directional lights, eight samples at a time, into buf.sample_color.
/// `small_weights`: rasterize_small left the barycentrics of its samples in buf.l1, buf.l2.
void shade_tile_fast(const FrameState& f, const Tile& tile, const SamplePattern& sp,
                     bool small_weights, TileBuffers& buf);

/// Stage 7 (resolve.cpp): the wireframe overlay on the tile's resolved colours (edges whose
/// depth passes against the deepest sample of the pixel).
void draw_wireframe(const FrameState& f, const Tile& tile, TileBuffers& buf, int S);

/// Adds each pixel's samples in buf.sample_color (`samples` per pixel) into out[pixel].
void accumulate_samples(const TileBuffers& buf, size_t pixels, int samples, Color* out);

/// Stage 7: divides the accumulated colours and AOVs by spp, draws the wireframe, and copies
/// the tile into `color` and the AOV images.
void resolve_tile(const FrameState& f, const Tile& tile, int spp, int last_pass_samples,
                  const AovTargets& targets, TileBuffers& buf, Image& color);

}  // namespace svetlo::raster
