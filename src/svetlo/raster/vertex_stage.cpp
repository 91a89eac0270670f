#include <algorithm>

#include "svetlo/core/parallel.h"
#include "svetlo/raster/fragment.h"
#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

ScreenVertex project(const PassGeometry& f, const ClipVertex& cv) {
    vec3 ndc = vec3(cv.clip) * cv.invw;
    vec2 px = f.cam.to_pixels(vec2(ndc));
    ScreenVertex s;
    s.x = to_fixed(px.x);
    s.y = to_fixed(px.y);
    // Depth key, smaller is nearer: -1/w for perspective (1/w is affine in screen space and
    // keeps float's relative precision at every distance, unlike z/w), window z for
    // orthographic cameras (w = 1, z/w linear in distance).
    // (A point at infinity, of weight 0, has the key 0: farther than any other.)
    s.z = f.cam.orthographic ? 0.5f * ndc.z + 0.5f : -cv.wh * cv.invw;
    return s;
}

/// Stage 2: the vertex stage. Clip coordinates of the list's world-space vertices, and for
/// Gouraud shading the lit colour of each vertex (one material per vertex: see
/// split_vertices_by_material; the geometric normal, which decides the side, is its first
/// face's).
void vertex_stage(const TriangleList& list, FrameState& f, int threads) {
    constexpr size_t kVertexChunk = 16384;
    const size_t count = list.positions.size();
    f.vertices.reuse(count);
    f.screen.reuse(count);
    const mat4 vp = f.cam.view_projection();
    const float gx = guard_x(f), gy = guard_y(f);
    const size_t chunks = (count + kVertexChunk - 1) / kVertexChunk;
    parallel_indices(chunks, threads, [&](size_t c) {
        for (size_t v = c * kVertexChunk; v < std::min(count, (c + 1) * kVertexChunk); ++v) {
            ClipVertex& out = f.vertices[v];
            out.world = list.positions[v];
            out.wh = list.w.empty() ? 1.0f : list.w[v];
            out.clip = vp * vec4(out.world, out.wh);
            out.normal = list.normals[v];
            out.uv = list.uvs[v];
            out.uv1 = list.uvs1.empty() ? out.uv : list.uvs1[v];
            out.vertex_color = list.colors.empty() ? vec4(1.0f) : list.colors[v];
            out.tangent = list.tangents.empty() ? vec4(0.0f) : list.tangents[v];
            out.color = Color(0.0f);
            // Projected here once when inside the clip volume; otherwise the triangles that
            // use it are clipped, and their pieces projected then.
            ScreenVertex& sv = f.screen[v];
            out.invw = 0.0f;
            sv = ScreenVertex{};
            if (inside(out.clip, gx, gy)) {
                out.invw = 1.0f / out.clip.w;
                sv = project(f, out);
                sv.inside = 1;
            }
        }
    });
    if (f.mode != Mode::Gouraud) return;
    if (f.per_light) f.vertex_light.assign(count * f.sources, Color(0.0f));
    std::vector<uint32_t> face_of(count, kNone);
    for (size_t t = 0; t < list.triangle_count(); ++t) {
        for (int c = 0; c < 3; ++c) {
            uint32_t v = list.indices[3 * t + c];
            if (face_of[v] == kNone) face_of[v] = static_cast<uint32_t>(t);
        }
    }
    parallel_indices(chunks, threads, [&](size_t c) {
        for (size_t v = c * kVertexChunk; v < std::min(count, (c + 1) * kVertexChunk); ++v) {
            if (face_of[v] == kNone) continue;
            size_t t = face_of[v];
            const ClipVertex* tv[3];
            for (int k = 0; k < 3; ++k) tv[k] = &f.vertices[list.indices[3 * t + k]];
            vec3 ng = triangle_normal(tv[0]->world, tv[1]->world, tv[2]->world);
            ClipVertex& out = f.vertices[v];
            vec3 wo = view_direction(f, out.world);
            Bsdf scratch;
            const Bsdf& bsdf = material_for_vertices(f, list.material[t], out.varyings(), scratch);
            out.color = f.per_light ? light_point_per_light(f, bsdf, out.world, wo, ng, out.normal,
                                                            &f.vertex_light[v * f.sources])
                                    : light_point(f, bsdf, out.world, wo, ng, out.normal);
        }
    });
}

}  // namespace svetlo::raster
