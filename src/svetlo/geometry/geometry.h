// Everything a ray can hit, in world space: the triangles of all meshes (transforms baked
// in) and the analytic shapes. Primitive ids: [0, T) are triangles, [T, T + S) shapes.
// Acceleration structures index the bounded primitives; infinite planes are tested apart.
// Instances are the one exception to "world space": a prototype's geometry, in its own space,
// placed by a transform (Placement; a hit on one names it in Hit::instance).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "svetlo/geometry/shapes.h"
#include "svetlo/geometry/triangle.h"

namespace svetlo {

/// The shading geometry of a hit.
struct SurfaceHit {
    vec3 p{0.0f};   // world-space point on the surface
    vec3 ng{0.0f};  // unit geometric normal: a triangle's CCW side, a shape's outside
    vec3 ns{0.0f};  // unit shading normal (interpolated on smooth meshes), same side as ng
    vec2 uv{0.0f};
    vec2 uv1{0.0f};    // the second texture coordinate set; uv where the surface has one
    vec4 color{1.0f};  // the vertex colour (Varyings::color)
    // The front side's unit tangent along increasing u, orthogonal to ns, and the bitangent's
    // side in w (Mesh::tangents); zero where the surface has none (no uvs, CSG, implicit).
    vec4 tangent{0.0f};
    // A clear coat's own shading normal, or zero: the coat takes ns (RtScene::surface sets it,
    // shading/normal_map.h's coat_shading_normal).
    vec3 coat_ns{0.0f};
    uint32_t material = 0;

    /// What the material's colours read here.
    Varyings varyings() const { return {uv, uv1, color}; }
    void set_varyings(const Varyings& at) {
        uv = at.uv[0];
        uv1 = at.uv[1];
        color = at.color;
    }
};

/// The varyings at barycentric point b (of corners 1 and 2) of the triangle with vertices
/// v[0..2]: each set and colour interpolated; an empty `uvs` gives b itself, an empty `uvs1`
/// set 0, empty `colors` white.
inline Varyings interpolate_varyings(const std::vector<vec2>& uvs, const std::vector<vec2>& uvs1,
                                     const std::vector<vec4>& colors, const uint32_t v[3], vec2 b) {
    const float b0 = 1.0f - b.x - b.y;
    const vec2 uv = uvs.empty() ? b : b0 * uvs[v[0]] + b.x * uvs[v[1]] + b.y * uvs[v[2]];
    return {
        uv, uvs1.empty() ? uv : b0 * uvs1[v[0]] + b.x * uvs1[v[1]] + b.y * uvs1[v[2]],
        colors.empty() ? vec4(1.0f) : b0 * colors[v[0]] + b.x * colors[v[1]] + b.y * colors[v[2]]};
}

/// The primitive ids [first, end) that one object became (empty when end <= first).
struct PrimitiveRange {
    uint32_t first = 0, end = 0;
};

/// A prototype's geometry placed once (docs/real-scenes.md, "Instances"). A ray meets it in
/// the prototype's space: the ray is carried there by the inverse transform, with the same t
/// (the map is affine and t is measured in units of |d|), and the surface found is carried
/// back.
struct Placement {
    uint32_t prototype = 0;  // index into Geometry::prototypes
    Transform to_world;      // the prototype's space to the world
    mat4 to_prototype{1.0f};
    mat3 normal_to_world{1.0f};  // inverse transpose of to_world's linear part
    bool mirrors = false;        // to_world turns a triangle's winding
    int material = -1;           // replaces the prototype's materials when >= 0
    Bounds3 bounds;              // of the placed prototype, in the world

    Ray to_prototype_ray(const Ray& r) const {
        return {vec3(to_prototype * vec4(r.o, 1.0f)), mat3(to_prototype) * r.d, r.tmax};
    }
};

class Geometry {
public:
    // Triangles: three indices each into the vertex arrays.
    std::vector<vec3> positions;
    std::vector<vec3> normals;   // empty, or per vertex (zero where the mesh has none)
    std::vector<vec2> uvs;       // empty, or per vertex
    std::vector<vec2> uvs1;      // empty, or per vertex (Mesh::uvs1; uvs where a mesh has none)
    std::vector<vec4> colors;    // empty, or per vertex (Mesh::colors; white where a mesh has none)
    std::vector<vec4> tangents;  // empty, or per vertex (zero where the mesh has none)
    std::vector<uint32_t> indices;
    std::vector<uint32_t> triangle_material;
    std::vector<AnalyticShape> shapes;
    // Instances: the prototypes' geometries (each in its own space, with no placements of its
    // own) and where they are placed. The primitives above are the world's own.
    std::vector<std::shared_ptr<const Geometry>> prototypes;
    std::vector<Placement> placements;

    uint32_t triangle_count() const { return static_cast<uint32_t>(triangle_material.size()); }
    uint32_t primitive_count() const {
        return triangle_count() + static_cast<uint32_t>(shapes.size());
    }
    bool is_triangle(uint32_t id) const { return id < triangle_count(); }
    const AnalyticShape& shape(uint32_t id) const { return shapes[id - triangle_count()]; }
    /// The material of a primitive; a CSG shape's leaves may differ (SurfaceHit has the one hit).
    uint32_t material(uint32_t id) const {
        return is_triangle(id) ? triangle_material[id] : shape(id).material;
    }
    /// The same for the primitive of a hit, in the world or in an instance.
    bool is_triangle(const Hit& hit) const {
        return hit.instance == Hit::kNone
                   ? is_triangle(hit.prim)
                   : prototypes[placements[hit.instance].prototype]->is_triangle(hit.prim);
    }
    uint32_t material(const Hit& hit) const {
        if (hit.instance == Hit::kNone) return material(hit.prim);
        const Placement& p = placements[hit.instance];
        return p.material >= 0 ? static_cast<uint32_t>(p.material)
                               : prototypes[p.prototype]->material(hit.prim);
    }

    /// Ids of the primitives with finite bounds (what acceleration structures hold), and of
    /// the infinite ones (planes), which every query tests directly.
    std::vector<uint32_t> bounded_primitives() const;
    /// The bounded primitives with ids from `first` on (shapes only, from triangle_count()).
    std::vector<uint32_t> bounded_primitives_from(uint32_t first) const;
    std::vector<uint32_t> unbounded_primitives() const;

    Bounds3 primitive_bounds(uint32_t id) const;

    /// Tests one primitive; on a hit closer than hit.t (initially the ray's tmax) updates hit.
    bool intersect(uint32_t id, const Ray& ray, const RayPrecomputed& pre, Hit& hit) const {
        if (id < triangle_count()) {
            const uint32_t* tri = &indices[3 * static_cast<size_t>(id)];
            float t, b1, b2;
            if (!intersect_triangle(ray, pre, positions[tri[0]], positions[tri[1]],
                                    positions[tri[2]], hit.t, t, b1, b2)) {
                return false;
            }
            hit.t = t;
            hit.prim = id;
            hit.u = b1;
            hit.v = b2;
            hit.part = 0;
            hit.sub = 0;
            hit.instance = Hit::kNone;
            return true;
        }
        ShapeHit sh;
        if (!intersect_shape(shape(id), ray, hit.t, sh)) return false;
        hit.t = sh.t;
        hit.prim = id;
        hit.u = sh.u;
        hit.v = sh.v;
        hit.part = sh.part;
        hit.sub = sh.sub;
        hit.instance = Hit::kNone;
        return true;
    }

    /// The closest hit among primitives ids[0, count), closer than hit.t; updates hit.
    bool intersect(const uint32_t* ids, size_t count, const Ray& ray, const RayPrecomputed& pre,
                   Hit& hit) const {
        bool found = false;
        for (size_t k = 0; k < count; ++k) found |= intersect(ids[k], ray, pre, hit);
        return found;
    }
    /// True when any of primitives ids[0, count) lies on the ray at 0 < t < ray.tmax.
    bool occludes(const uint32_t* ids, size_t count, const Ray& ray,
                  const RayPrecomputed& pre) const {
        for (size_t k = 0; k < count; ++k) {
            Hit hit;
            hit.t = ray.tmax;
            if (intersect(ids[k], ray, pre, hit)) return true;
        }
        return false;
    }

    /// The surface at a hit, in the world (a hit in an instance carried out of its prototype's
    /// space, its material the placement's where it replaces the prototype's).
    SurfaceHit surface(const Ray& ray, const Hit& hit) const;

    /// The bounds of the bounded primitives and of the placements.
    Bounds3 bounds() const;

    /// Bytes held by the triangle and shape arrays, the placements and the prototypes.
    size_t memory_bytes() const;
};

}  // namespace svetlo
