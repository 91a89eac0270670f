#include "svetlo/geometry/geometry.h"

#include "svetlo/scene/tangents.h"

namespace svetlo {

namespace {

bool is_bounded(const AnalyticShape& s) {
    if (s.kind == ShapeKind::Plane) return false;
    Bounds3 b = shape_bounds(s);
    return std::isfinite(b.min.x + b.min.y + b.min.z + b.max.x + b.max.y + b.max.z);
}

}  // namespace

std::vector<uint32_t> Geometry::bounded_primitives() const { return bounded_primitives_from(0); }

std::vector<uint32_t> Geometry::bounded_primitives_from(uint32_t first) const {
    std::vector<uint32_t> ids;
    ids.reserve(primitive_count() - std::min(first, primitive_count()));
    for (uint32_t id = first; id < primitive_count(); ++id) {
        if (is_triangle(id) || is_bounded(shape(id))) ids.push_back(id);
    }
    return ids;
}

std::vector<uint32_t> Geometry::unbounded_primitives() const {
    std::vector<uint32_t> ids;
    for (uint32_t id = triangle_count(); id < primitive_count(); ++id) {
        if (!is_bounded(shape(id))) ids.push_back(id);
    }
    return ids;
}

Bounds3 Geometry::primitive_bounds(uint32_t id) const {
    if (!is_triangle(id)) return shape_bounds(shape(id));
    Bounds3 b;
    for (int k = 0; k < 3; ++k) b.extend(positions[indices[3 * static_cast<size_t>(id) + k]]);
    return b;
}

SurfaceHit Geometry::surface(const Ray& ray, const Hit& hit) const {
    if (hit.instance != Hit::kNone) {
        const Placement& place = placements[hit.instance];
        const Geometry& prototype = *prototypes[place.prototype];
        Hit local = hit;
        local.instance = Hit::kNone;
        SurfaceHit s = prototype.surface(place.to_prototype_ray(ray), local);
        s.p = place.to_world.point(s.p);
        // A triangle's geometric normal is its counter-clockwise side, in the world as in the
        // prototype: a mirroring placement turns it (a shape's stays outside).
        const bool turn = place.mirrors && prototype.is_triangle(hit.prim);
        s.ng = glm::normalize(place.normal_to_world * s.ng) * (turn ? -1.0f : 1.0f);
        s.ns = glm::normalize(place.normal_to_world * s.ns);
        if (glm::dot(s.ns, s.ng) < 0.0f) s.ns = -s.ns;
        s.tangent = orthogonal_tangent(transform_tangent(place.to_world, s.tangent), s.ns);
        if (place.material >= 0) s.material = static_cast<uint32_t>(place.material);
        return s;
    }
    SurfaceHit s;
    s.material = material(hit.prim);
    if (!is_triangle(hit.prim)) {
        ShapeHit sh;
        sh.t = hit.t;
        sh.part = hit.part;
        sh.sub = hit.sub;
        sh.u = hit.u;
        sh.v = hit.v;
        ShapeSurface ss = shape_surface(shape(hit.prim), ray, sh);
        s.p = ss.p;
        s.ng = ss.n;
        s.ns = ss.ns;
        s.uv = s.uv1 = ss.uv;
        s.material = ss.material;
        s.tangent = orthogonal_tangent(ss.tangent, s.ns);
        return s;
    }
    const uint32_t* tri = &indices[3 * static_cast<size_t>(hit.prim)];
    vec3 p0 = positions[tri[0]], p1 = positions[tri[1]], p2 = positions[tri[2]];
    float b0 = 1.0f - hit.u - hit.v;
    // The barycentric point is more accurate than o + t d (pbrt-v4, section 6.8.6).
    s.p = b0 * p0 + hit.u * p1 + hit.v * p2;
    s.ng = triangle_normal(p0, p1, p2);
    s.ns = s.ng;
    if (!normals.empty()) {
        vec3 n = b0 * normals[tri[0]] + hit.u * normals[tri[1]] + hit.v * normals[tri[2]];
        float len = glm::length(n);
        if (len > 1e-12f) s.ns = glm::dot(n, s.ng) < 0.0f ? -n / len : n / len;
    }
    s.set_varyings(interpolate_varyings(uvs, uvs1, colors, tri, vec2(hit.u, hit.v)));
    if (!tangents.empty()) {
        const vec4 t = b0 * tangents[tri[0]] + hit.u * tangents[tri[1]] + hit.v * tangents[tri[2]];
        // The sign is a vertex's; a triangle whose corners disagree takes its first corner's.
        s.tangent = orthogonal_tangent(vec4(vec3(t), tangents[tri[0]].w), s.ns);
    }
    return s;
}

Bounds3 Geometry::bounds() const {
    Bounds3 b;
    for (uint32_t id : bounded_primitives()) b.extend(primitive_bounds(id));
    for (const Placement& p : placements) b.extend(p.bounds);
    return b;
}

size_t Geometry::memory_bytes() const {
    size_t placed = placements.size() * sizeof(Placement) +
                    prototypes.size() * sizeof(std::shared_ptr<const Geometry>);
    for (const auto& p : prototypes) placed += p->memory_bytes();
    return placed + positions.size() * sizeof(vec3) + normals.size() * sizeof(vec3) +
           (uvs.size() + uvs1.size()) * sizeof(vec2) +
           (tangents.size() + colors.size()) * sizeof(vec4) + indices.size() * sizeof(uint32_t) +
           triangle_material.size() * sizeof(uint32_t) + shapes.size() * sizeof(AnalyticShape);
}

}  // namespace svetlo
