#include "svetlo/raster/fragment.h"

#include <algorithm>
#include <new>

#include "svetlo/scene/tangents.h"
#include "svetlo/shading/normal_map.h"
#include "svetlo/shading/shading_frame.h"
#include "svetlo/shading/texture.h"

namespace svetlo::raster {

const Bsdf& material_at(const FrameShading& f, uint32_t m, const SurfaceUv& at, Bsdf& scratch) {
    if (!f.textured[m]) return f.constant_bsdf[m];
    // Made where it stays (a placement new of the returned value, which C++17 builds in
    // place): assigned, it was built in a temporary and copied, and the copy's wide loads of
    // the temporary's just-written narrow stores stalled (most of this function's time).
    return *::new (static_cast<void*>(&scratch))
        Bsdf(make_bsdf(f.materials[m], at.varyings(), at.lookup(f)));
}

const Bsdf& material_for_vertices(const FrameShading& f, uint32_t m, const Varyings& at,
                                  Bsdf& scratch) {
    if (!f.modulate[m]) {
        SurfaceUv point;
        point.uv = at.uv[0];
        point.uv1 = at.uv[1];
        point.color = at.color;
        return material_at(f, m, point, scratch);
    }
    scratch = make_bsdf(f.lit_white[m], at, TextureLookup{f.scene->textures});
    return scratch;
}

Color light_point(const FrameShading& f, const Bsdf& bsdf, vec3 p, vec3 wo, vec3 ng, vec3 ns,
                  const LightVisibility& vis, size_t sample) {
    return shade_point(bsdf, p, make_shading_frame(ng, ns, wo), wo, *f.lights,
                       f.scene->render.ambient, f.scene->render.background, vis, sample);
}

Color light_point_per_light(const FrameShading& f, const Bsdf& bsdf, vec3 p, vec3 wo, vec3 ng,
                            vec3 ns, Color* per_light) {
    return shade_point_per_light(bsdf, p, make_shading_frame(ng, ns, wo), wo, *f.lights,
                                 f.scene->render.ambient, f.scene->render.background, per_light);
}

Color flat_colour(const FrameState& f, const uint32_t idx[3], uint32_t material, Color* per_light) {
    const ClipVertex* cv[3] = {&f.vertices[idx[0]], &f.vertices[idx[1]], &f.vertices[idx[2]]};
    vec3 p = (cv[0]->world + cv[1]->world + cv[2]->world) / 3.0f;
    vec3 ng = triangle_normal(cv[0]->world, cv[1]->world, cv[2]->world);
    const Varyings at((cv[0]->uv + cv[1]->uv + cv[2]->uv) / 3.0f,
                      (cv[0]->uv1 + cv[1]->uv1 + cv[2]->uv1) / 3.0f,
                      (cv[0]->vertex_color + cv[1]->vertex_color + cv[2]->vertex_color) / 3.0f);
    vec3 wo = view_direction(f, p);
    Bsdf scratch;
    const Bsdf& bsdf = material_for_vertices(f, material, at, scratch);
    if (per_light) return light_point_per_light(f, bsdf, p, wo, ng, ng, per_light);
    return light_point(f, bsdf, p, wo, ng, ng);
}

UvGradients uv_gradients(const FrameState& f, const SetupTriangle& t, const ClipVertex& A,
                         const ClipVertex& B, const ClipVertex& C) {
    UvGradients g;
    g.footprint = f.needs_footprint[t.material];
    if (!g.footprint) return g;
    // The screen-space barycentric gradients (a / area per pixel) through the perspective
    // division.
    Edge e[3] = {Edge::make(t.x[1], t.y[1], t.x[2], t.y[2]),
                 Edge::make(t.x[2], t.y[2], t.x[0], t.y[0]),
                 Edge::make(t.x[0], t.y[0], t.x[1], t.y[1])};
    auto area = static_cast<float>(signed_area2(t.x, t.y));
    const float invw[3] = {A.invw, B.invw, C.invw};
    for (int axis = 0; axis < 2; ++axis) {
        for (int i = 0; i < 3; ++i) {
            float dl = static_cast<float>(axis == 0 ? e[i].a : e[i].b) * kSubpixel / area;
            g.dq[axis][i] = dl * invw[i];
            g.dsum[axis] += g.dq[axis][i];
        }
    }
    return g;
}

namespace {

/// surface_uv's footprint of set `set` (ClipVertex::uv or uv1), inlined where surface_uvs
/// calls it lane by lane: d(q_i / sum q) = (dq_i sum - q_i dsum) / sum^2 per screen axis,
/// times the uvs.
[[gnu::always_inline]] inline void footprint(const UvGradients& g, const ClipVertex& A,
                                             const ClipVertex& B, const ClipVertex& C,
                                             const Weights& w, vec2 (&d)[2],
                                             vec2 ClipVertex::*set = &ClipVertex::uv) {
    const vec2* uvs[3] = {&(A.*set), &(B.*set), &(C.*set)};
    const float sum = w.q[0] + w.q[1] + w.q[2];
    for (int axis = 0; axis < 2; ++axis) {
        d[axis] = vec2(0.0f);
        for (int i = 0; i < 3; ++i)
            d[axis] += ((g.dq[axis][i] * sum - w.q[i] * g.dsum[axis]) / (sum * sum)) * *uvs[i];
    }
}

[[gnu::always_inline]] inline vec2 uv_at(const ClipVertex& A, const ClipVertex& B,
                                         const ClipVertex& C, const Weights& w) {
    return w.b[0] * A.uv + w.b[1] * B.uv + w.b[2] * C.uv;
}

}  // namespace

SurfaceUv surface_uv(const UvGradients& g, const ClipVertex& A, const ClipVertex& B,
                     const ClipVertex& C, const Weights& w) {
    SurfaceUv r;
    const Varyings at = varyings_at(A, B, C, w.b);
    r.uv = at.uv[0];
    r.uv1 = at.uv[1];
    r.color = at.color;
    if (!g.footprint) return r;
    vec2 d[2];
    footprint(g, A, B, C, w, d);
    r.duv_dx = d[0];
    r.duv_dy = d[1];
    footprint(g, A, B, C, w, d, &ClipVertex::uv1);
    r.duv1_dx = d[0];
    r.duv1_dy = d[1];
    return r;
}

void surface_uvs(const UvGradients& g, const ClipVertex& A, const ClipVertex& B,
                 const ClipVertex& C, const float* l1, const float* l2, int n, SurfaceUv* out) {
    // Made into arrays of floats (which the compiler vectorizes), then copied out.
    // The weights once per lane; the footprint's loop apart (with the uvs' in one loop,
    // the compiler vectorized neither).
    alignas(32) float v[6][kTile] = {}, q[3][kTile], b[3][kTile];
    for (int k = 0; k < n; ++k) {
        const Weights w = perspective_weights(vec2(l1[k], l2[k]), A, B, C);
        const vec2 uv = uv_at(A, B, C, w);
        v[0][k] = uv.x;
        v[1][k] = uv.y;
        for (int i = 0; i < 3; ++i) {
            q[i][k] = w.q[i];
            b[i][k] = w.b[i];
        }
    }
    if (g.footprint) {
        for (int k = 0; k < n; ++k) {
            const Weights w{{q[0][k], q[1][k], q[2][k]}, {b[0][k], b[1][k], b[2][k]}};
            vec2 d[2];
            footprint(g, A, B, C, w, d);
            v[2][k] = d[0].x;
            v[3][k] = d[0].y;
            v[4][k] = d[1].x;
            v[5][k] = d[1].y;
        }
    }
    for (int k = 0; k < n; ++k)
        out[k] = SurfaceUv{vec2(v[0][k], v[1][k]), vec2(v[2][k], v[3][k]), vec2(v[4][k], v[5][k])};
}

SurfaceUv surface_uv(const FrameState& f, const SetupTriangle& t, const ClipVertex& A,
                     const ClipVertex& B, const ClipVertex& C, const Weights& w) {
    return surface_uv(uv_gradients(f, t, A, B, C), A, B, C, w);
}

namespace {

struct ShadeResult {
    Color color{0.0f};
    float distance = 0.0f;
    vec3 normal{0.0f};
    Color albedo{0.0f};
    /// Its AOVs but the visibility, which shade_tile adds for every sample (light 0's mask).
    AovSample aov() const { return AovSample{distance, normal, albedo, 0.0f}; }
};

/// Stage 6: the colour of a visible sample of triangle `ti` with screen barycentrics (l1, l2).
/// `vis` and `sample`: the lights' visibility at this sample of the tile.
/// The material's normal maps at a sample (normal_map.h): ns bent by the surface's map, and
/// coat_ns set to the clear coat's own normal; both untouched where neither has a map.
void bend_normals(const FrameState& f, const SetupTriangle& t, const Weights& w,
                  const SurfaceUv& at, vec3 ng, vec3& ns, vec3& coat_ns) {
    const Material& material = f.materials[t.material];
    const NormalMap& map = material.normal_map;
    const NormalMap* coat_map = coat_normal_map(material);
    if (!map.present() && !coat_map) return;
    const ClipVertex& A = f.vertex(t.v[0]);
    const ClipVertex& B = f.vertex(t.v[1]);
    const ClipVertex& C = f.vertex(t.v[2]);
    if (glm::dot(ns, ng) < 0.0f) ns = -ns;  // onto the front side, as the ray tracers'
    const vec4 tangent = orthogonal_tangent(
        vec4(w.b[0] * vec3(A.tangent) + w.b[1] * vec3(B.tangent) + w.b[2] * vec3(C.tangent),
             A.tangent.w),
        ns);
    coat_ns = coat_shading_normal(
        material,
        coat_map ? eval_color(coat_map->texture, at.varyings(), at.lookup(f)) : Color(0.0f), ns, ng,
        tangent);
    if (map.present())
        ns = mapped_normal(map, eval_color(map.texture, at.varyings(), at.lookup(f)), ns, ng,
                           tangent);
}

ShadeResult shade_sample(const FrameState& f, uint32_t ti, const TriangleEdges& edges, int64_t sx,
                         int64_t sy, bool want_aovs, const LightVisibility& vis, size_t sample) {
    const SetupTriangle& t = f.tri(ti);
    if (f.mode == Mode::Flat && !want_aovs && !f.modulate[t.material] && !f.per_light) {
        ShadeResult flat;
        flat.color = f.flat_color(ti);
        return flat;
    }
    const ClipVertex& A = f.vertex(t.v[0]);
    const ClipVertex& B = f.vertex(t.v[1]);
    const ClipVertex& C = f.vertex(t.v[2]);
    Weights w = perspective_weights(edges.weights(sx, sy), A, B, C);
    float b0 = w.b[0], b1 = w.b[1], b2 = w.b[2];
    ShadeResult r;
    vec3 p = b0 * A.world + b1 * B.world + b2 * C.world;
    vec3 ng = face_normal(t, A, B, C);
    vec3 ns = b0 * A.normal + b1 * B.normal + b2 * C.normal;
    ns = glm::length(ns) > 0.0f ? glm::normalize(ns) : ng;
    vec3 wo = view_direction(f, p);
    const SurfaceUv at = surface_uv(f, t, A, B, C, w);
    vec3 coat_ns(0.0f);  // the clear coat's own normal (coat_shading_normal), or none
    bend_normals(f, t, w, at, ng, ns, coat_ns);
    if (want_aovs || f.mode == Mode::Normal || f.mode == Mode::Depth) {
        r.distance = f.cam.orthographic ? glm::dot(p - f.cam.eye, f.cam.forward)
                                        : glm::length(p - f.cam.eye);
        r.normal = make_shading_frame(ng, ns, wo).ns;
    }
    // GL_MODULATE: flat and Gouraud light times the base colour's texture at this sample.
    auto modulated = [&](Color lit) {
        const ColorSource* base = f.modulate[t.material];
        if (!base) return lit;
        return lit * eval_color(*base, at.varyings(), at.lookup(f));
    };
    switch (f.mode) {
        case Mode::Flat: {
            Color lit = f.flat_color(ti);
            if (f.per_light) {
                const Color* terms = &f.face_light[f.source(ti) * f.sources];
                for (size_t k = 0; k < f.sources; ++k) lit += vis.at(k, sample) * terms[k];
            }
            r.color = modulated(lit);
            break;
        }
        case Mode::Gouraud: {
            Color lit = b0 * A.color + b1 * B.color + b2 * C.color;
            if (f.per_light) {
                // Each light's vertex terms, interpolated over the list's own triangle (the
                // sample's barycentrics there, by areas: clipping made A, B, C).
                const uint32_t* v = &f.list->indices[3 * static_cast<size_t>(f.source(ti))];
                const vec3 a = f.list->positions[v[0]], b = f.list->positions[v[1]],
                           c = f.list->positions[v[2]];
                const vec3 n = glm::cross(b - a, c - a);
                const float inv = 1.0f / std::max(glm::dot(n, n), 1e-30f);
                const float wb = glm::dot(glm::cross(p - a, c - a), n) * inv;
                const float wc = glm::dot(glm::cross(b - a, p - a), n) * inv;
                const float wa = 1.0f - wb - wc;
                for (size_t k = 0; k < f.sources; ++k) {
                    lit += vis.at(k, sample) * (wa * f.vertex_light[v[0] * f.sources + k] +
                                                wb * f.vertex_light[v[1] * f.sources + k] +
                                                wc * f.vertex_light[v[2] * f.sources + k]);
                }
            }
            r.color = modulated(lit);
            break;
        }
        case Mode::Depth: {
            float depth = f.cam.orthographic ? r.distance : glm::dot(p - f.cam.eye, f.cam.forward);
            r.color = Color(
                std::clamp(1.0f - (depth - f.cam.near) / (f.cam.far - f.cam.near), 0.0f, 1.0f));
            break;
        }
        case Mode::Normal:
            r.color = 0.5f * r.normal + vec3(0.5f);
            break;
        case Mode::Overdraw:  // the stencil buffer's count, not a colour of the surface
            break;
        case Mode::Phong: {
            Bsdf scratch;
            const Bsdf& bsdf = material_at(f, t.material, at, scratch);
            if (glm::dot(coat_ns, coat_ns) > 0.0f) {  // the coat's own normal, on a copy
                Bsdf with_coat = bsdf;
                with_coat.coat_normal =
                    seen_coat_normal(coat_ns, make_shading_frame(ng, ns, wo), wo);
                r.color = light_point(f, with_coat, p, wo, ng, ns, vis, sample);
            } else {
                r.color = light_point(f, bsdf, p, wo, ng, ns, vis, sample);
            }
            if (want_aovs) r.albedo = albedo_of(bsdf);
            return r;
        }
    }
    if (want_aovs) {
        Bsdf scratch;
        SurfaceUv point = at;  // the albedo AOV without the footprint
        point.duv_dx = point.duv_dy = point.duv1_dx = point.duv1_dy = vec2(0.0f);
        const Bsdf& bsdf = material_at(f, t.material, point, scratch);
        r.albedo = albedo_of(bsdf);
    }
    return r;
}

}  // namespace

Color shade_one(const FrameState& f, uint32_t tri, EdgeCache& edges, int64_t sx, int64_t sy,
                const LightVisibility& vis, size_t sample) {
    return shade_sample(f, tri, edges.of(tri), sx, sy, false, vis, sample).color;
}

void shade_tile(const FrameState& f, const Tile& tile, const SamplePattern& sp, bool msaa,
                bool aovs, TileBuffers& buf) {
    const int S = sp.count;
    const size_t pixels = static_cast<size_t>(tile.x1 - tile.x0) * (tile.y1 - tile.y0);
    const Color background = f.scene->render.background;
    const ImageBasedLighting& ibl = f.lights->environment;
    const FilmRays rays(f.cam);
    EdgeCache edges(f);
    const LightVisibility vis = light_visibility(buf, pixels * static_cast<size_t>(S));
    auto shade = [&](uint32_t tri, size_t pixel, int s, bool want_aovs) {
        return shade_sample(f, tri, edges.of(tri), sample_x(tile, pixel, sp, s),
                            sample_y(tile, pixel, sp, s), want_aovs, vis,
                            pixel * static_cast<size_t>(S) + static_cast<size_t>(s));
    };
    for (size_t pixel = 0; pixel < pixels; ++pixel) {
        Color sum(0.0f);
        AovSum aov_sum;
        for (int s = 0; s < S; ++s) {
            size_t i = pixel * static_cast<size_t>(S) + static_cast<size_t>(s);
            uint32_t tri = buf.tri[i];
            // The visibility AOV: light 0's mask, 1 where nothing is hit.
            aov_sum.visibility += tri == kNone || f.light0_source < 0
                                      ? 1.0f
                                      : vis.at(static_cast<size_t>(f.light0_source), i);
            if (f.mode == Mode::Overdraw) {
                sum += Color(static_cast<float>(buf.stencil[i]) / kOverdrawPerUnit);
                if (tri == kNone || !aovs) continue;
                aov_sum.add(shade(tri, pixel, s, true).aov());
                continue;
            }
            if (tri == kNone) {  // the background, or the map along the sample's ray
                sum += ibl.active() ? ibl.seen(rays, sample_x(tile, pixel, sp, s),
                                               sample_y(tile, pixel, sp, s))
                                    : background;
                continue;
            }
            float w = 1.0f;
            if (msaa) {
                bool seen = false;  // already shaded for an earlier sample?
                for (int k = 0; k < s && !seen; ++k) seen = buf.tri[pixel * S + k] == tri;
                if (seen) continue;
                int covered = 0;
                for (int k = s; k < S; ++k) covered += buf.tri[pixel * S + k] == tri ? 1 : 0;
                w = static_cast<float>(covered);
            }
            ShadeResult r = shade(tri, pixel, s, aovs);
            if (!is_finite(r.color)) {  // dropped (black) and counted
                ++buf.nonfinite;
                continue;
            }
            sum += msaa ? w * r.color : r.color;
            aov_sum.add(r.aov(), w);
        }
        buf.color[pixel] += sum;
        if (aovs) buf.aov[pixel].add(aov_sum);
    }
}

}  // namespace svetlo::raster
