#include "svetlo/scene/tangents.h"

#include <algorithm>
#include <cmath>

namespace svetlo {

namespace {

/// The angle at corner a of triangle (a, b, c), radians.
float corner_angle(vec3 a, vec3 b, vec3 c) {
    const vec3 u = b - a, v = c - a;
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

}  // namespace

std::vector<vec4> mesh_tangents(const Mesh& mesh) {
    const size_t n = mesh.positions.size();
    if (mesh.uvs.size() != n) return {};
    std::vector<vec3> tangent(n, vec3(0.0f)), bitangent(n, vec3(0.0f)), normal(n, vec3(0.0f));
    // A vertex without a normal (none given, or zero: a flat glTF primitive) takes the
    // angle-weighted normal of its triangles.
    const auto given = [&](size_t v) {
        return mesh.normals.size() == n && glm::dot(mesh.normals[v], mesh.normals[v]) > 0.0f;
    };
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const uint32_t* v = &mesh.indices[3 * t];
        const vec3 p[3] = {mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]};
        const vec2 w[3] = {mesh.uvs[v[0]], mesh.uvs[v[1]], mesh.uvs[v[2]]};
        // dp = dp/du du + dp/dv dv along two edges, solved for the gradients (pbrt-v4 3.8).
        const vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        const vec2 d1 = w[1] - w[0], d2 = w[2] - w[0];
        const float det = d1.x * d2.y - d1.y * d2.x;
        const vec3 face_n = glm::cross(e1, e2);
        if (!std::isfinite(det) || std::abs(det) < 1e-20f || glm::dot(face_n, face_n) == 0.0f)
            continue;  // no uv area (or no area): no direction to give
        const float inv = 1.0f / det;
        const vec3 dpdu = (d2.y * e1 - d1.y * e2) * inv;
        const vec3 dpdv = (d1.x * e2 - d2.x * e1) * inv;
        if (!std::isfinite(glm::dot(dpdu, dpdu) + glm::dot(dpdv, dpdv))) continue;
        const vec3 unit_face_n = glm::normalize(face_n);
        for (int k = 0; k < 3; ++k) {
            const float angle = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            const vec3 nv = given(v[k]) ? mesh.normals[v[k]] : unit_face_n;
            // Each gradient's part in the vertex's tangent plane, unit, weighted by the angle.
            auto in_plane = [&](vec3 d) {
                const vec3 q = d - nv * glm::dot(nv, d);
                const float len = glm::length(q);
                return len > 0.0f ? q * (angle / len) : vec3(0.0f);
            };
            tangent[v[k]] += in_plane(dpdu);
            bitangent[v[k]] += in_plane(dpdv);
            normal[v[k]] += angle * unit_face_n;
        }
    }
    std::vector<vec4> out(n, vec4(0.0f));
    for (size_t k = 0; k < n; ++k) {
        vec3 nv = given(k) ? mesh.normals[k] : normal[k];
        const float len = glm::length(nv);
        if (!(len > 0.0f)) continue;
        nv /= len;
        const vec4 t = orthogonal_tangent(vec4(tangent[k], 1.0f), nv);
        if (t.w == 0.0f) continue;
        const float side = glm::dot(glm::cross(nv, vec3(t)), bitangent[k]);
        out[k] = vec4(vec3(t), side < 0.0f ? -1.0f : 1.0f);
    }
    return out;
}

void add_missing_tangents(Scene& scene) {
    auto mapped = [&](int m) {
        return m >= 0 && static_cast<size_t>(m) < scene.materials.size() &&
               scene.materials[static_cast<size_t>(m)].has_normal_map();
    };
    // `also`: a material that replaces the object's somewhere (an instance's) has a normal map.
    auto add = [&](Object& obj, bool also) {
        auto* mesh = std::get_if<Mesh>(&obj.shape);
        if (!mesh || mesh->uvs.empty()) return;
        // A file's tangents are kept; vertices it gave none (a glTF primitive without TANGENT
        // beside one with) get made ones.
        const auto none = [](const vec4& t) { return t.w == 0.0f; };
        if (!mesh->tangents.empty() &&
            std::none_of(mesh->tangents.begin(), mesh->tangents.end(), none))
            return;
        bool needed = also || mapped(obj.material);
        if (obj.material < 0)
            needed = needed ||
                     std::any_of(mesh->face_material.begin(), mesh->face_material.end(), mapped);
        if (!needed) return;
        std::vector<vec4> made = mesh_tangents(*mesh);
        if (mesh->tangents.empty()) {
            mesh->tangents = std::move(made);
            return;
        }
        for (size_t k = 0; k < made.size(); ++k)
            if (none(mesh->tangents[k])) mesh->tangents[k] = made[k];
    };
    for (Object& obj : scene.objects) add(obj, false);
    std::vector<char> replaced_by_mapped(scene.prototypes.size(), 0);
    for (const Instance& i : scene.instances)
        if (mapped(i.material)) replaced_by_mapped[i.prototype] = 1;
    for (size_t p = 0; p < scene.prototypes.size(); ++p)
        for (Object& obj : scene.prototypes[p].objects) add(obj, replaced_by_mapped[p] != 0);
}

vec4 orthogonal_tangent(vec4 t, vec3 ns) {
    const vec3 q = vec3(t) - ns * glm::dot(ns, vec3(t));
    const float len2 = glm::dot(q, q);
    // Gram-Schmidt: a tangent within about 0.06 degrees of the normal gives no frame.
    if (!(len2 > 1e-12f * glm::dot(vec3(t), vec3(t))) || !std::isfinite(len2)) return vec4(0.0f);
    return vec4(q / std::sqrt(len2), t.w < 0.0f ? -1.0f : 1.0f);
}

}  // namespace svetlo
