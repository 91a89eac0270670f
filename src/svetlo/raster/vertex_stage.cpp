#include "svetlo/core/parallel.h"
#include "svetlo/raster/fragment.h"
#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

ScreenVertex project(const FrameState& f, const ClipVertex& cv) {
    vec3 ndc = vec3(cv.clip) * cv.invw;
    vec2 px = f.cam.to_pixels(vec2(ndc));
    ScreenVertex s;
    s.x = to_fixed(px.x);
    s.y = to_fixed(px.y);
    // Depth key, smaller is nearer: -1/w for perspective (1/w is affine in screen space and
    // keeps float's relative precision at every distance, unlike z/w), window z for
    // orthographic cameras (w = 1, z/w linear in distance).
    s.z = f.ortho ? 0.5f * ndc.z + 0.5f : -cv.invw;
    return s;
}

/// Stage 2: the vertex stage. World positions and normals, clip coordinates, and for
/// Gouraud shading the lit colour of each vertex (one material per vertex: see
/// split_vertices_by_material; the geometric normal, which decides the side, is its first
/// face's).
void vertex_stage(const std::vector<DrawMesh>& meshes, FrameState& f, std::vector<uint32_t>& base,
                  int threads) {
    base.assign(meshes.size() + 1, 0);
    for (size_t k = 0; k < meshes.size(); ++k)
        base[k + 1] = base[k] + static_cast<uint32_t>(meshes[k].mesh.positions.size());
    f.vertices.reuse(base.back());
    f.screen.reuse(base.back());
    mat4 vp = f.cam.view_projection();
    float gx = guard_x(f), gy = guard_y(f);
    parallel_indices(meshes.size(), threads, [&](size_t k) {
        const Mesh& m = meshes[k].mesh;
        const mat4& model = meshes[k].model;
        mat3 nm = normal_matrix(model);
        for (size_t v = 0; v < m.positions.size(); ++v) {
            ClipVertex& out = f.vertices[base[k] + v];
            out.world = vec3(model * vec4(m.positions[v], 1.0f));
            out.clip = vp * vec4(out.world, 1.0f);
            vec3 n = v < m.normals.size() ? m.normals[v] : vec3(0.0f);
            vec3 tn = nm * n;
            float len2 = glm::dot(tn, tn);
            out.normal = len2 > 0.0f ? tn * (1.0f / std::sqrt(len2)) : vec3(0.0f);
            out.uv = v < m.uvs.size() ? m.uvs[v] : vec2(0.0f);
            out.color = Color(0.0f);
            // Projected here once when inside the clip volume; otherwise the triangles that
            // use it are clipped, and their pieces projected then.
            ScreenVertex& sv = f.screen[base[k] + v];
            out.invw = 0.0f;
            sv = ScreenVertex{};
            if (inside(out.clip, gx, gy)) {
                out.invw = 1.0f / out.clip.w;
                sv = project(f, out);
                sv.inside = 1;
            }
        }
        if (f.mode != Mode::Gouraud) return;
        std::vector<uint32_t> face_of(m.positions.size(), kNone);
        for (size_t t = 0; t < m.triangle_count(); ++t) {
            for (int c = 0; c < 3; ++c) {
                uint32_t v = m.indices[3 * t + c];
                if (face_of[v] == kNone) face_of[v] = static_cast<uint32_t>(t);
            }
        }
        for (size_t v = 0; v < m.positions.size(); ++v) {
            if (face_of[v] == kNone) continue;
            size_t t = face_of[v];
            const ClipVertex* tv[3];
            for (int c = 0; c < 3; ++c) tv[c] = &f.vertices[base[k] + m.indices[3 * t + c]];
            vec3 ng =
                unit_or_z(glm::cross(tv[1]->world - tv[0]->world, tv[2]->world - tv[0]->world));
            ClipVertex& out = f.vertices[base[k] + v];
            auto mat = static_cast<uint32_t>(m.face_material[t]);
            vec3 wo = f.ortho ? -f.forward : glm::normalize(f.eye - out.world);
            Bsdf scratch;
            out.color = light_point(f, material_at(f, mat, out.uv, vec2(0.0f), vec2(0.0f), scratch),
                                    out.world, wo, ng, out.normal);
        }
    });
}

}  // namespace svetlo::raster
