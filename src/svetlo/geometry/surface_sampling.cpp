#include "svetlo/geometry/surface_sampling.h"

#include "svetlo/core/sampling.h"

namespace svetlo {

namespace {

/// A uniform point on an analytic shape in object space, with its outward normal and the part
/// it lies on (matching shape_surface's parts).
void sample_shape_local(const AnalyticShape& s, vec2 u, float u_part, vec3& p, vec3& n, int& part) {
    part = 0;
    switch (s.kind) {
        case ShapeKind::Sphere: {
            n = sample_uniform_sphere(u);
            p = s.p0 + s.radius * n;
            return;
        }
        case ShapeKind::Box: {
            vec3 e = s.p1 - s.p0;
            float areas[3] = {e.y * e.z, e.z * e.x, e.x * e.y};
            // Six faces, min and max side of each axis, chosen in proportion to area.
            float x = u_part * 2.0f * (areas[0] + areas[1] + areas[2]);
            int face = 0;
            while (face < 5 && x >= areas[face / 2]) x -= areas[face++ / 2];
            const BoxSide side = box_side(s.p0, s.p1, face);
            p = side.corner + u.x * side.edge_u + u.y * side.edge_v;
            n = side.n;
            part = face;
            return;
        }
        default: {  // cylinder and cone, in the axis frame
            float r = s.radius, h = s.height;
            bool cone = s.kind == ShapeKind::Cone;
            float slant = cone ? std::sqrt(r * r + h * h) : 0.0f;
            float lateral = cone ? kPi * r * slant : 2.0f * kPi * r * h;
            float cap = kPi * r * r;
            float total = lateral + cap * (cone ? 1.0f : 2.0f);
            float x = u_part * total;
            vec3 q, ln;
            if (x < lateral) {
                float phi = 2.0f * kPi * u.x;
                if (cone) {
                    float f = std::sqrt(u.y);  // area grows linearly with distance from the apex
                    float z = h * (1.0f - f);
                    q = vec3(r * f * std::cos(phi), r * f * std::sin(phi), z);
                    ln = glm::normalize(vec3(q.x, q.y, square(r / h) * (h - z)));
                } else {
                    q = vec3(r * std::cos(phi), r * std::sin(phi), h * u.y);
                    ln = vec3(std::cos(phi), std::sin(phi), 0.0f);
                }
                part = 0;
            } else {
                vec2 d = r * sample_disk_concentric(u);
                bool top = !cone && x >= lateral + cap;
                q = vec3(d.x, d.y, top ? h : 0.0f);
                ln = vec3(0.0f, 0.0f, top ? 1.0f : -1.0f);
                part = top ? 2 : 1;
            }
            p = s.p0 + s.frame.to_world(q);
            n = s.frame.to_world(ln);
            return;
        }
    }
}

}  // namespace

BoxSide box_side(vec3 lo, vec3 hi, int side) {
    const int axis = side / 2, a = (axis + 1) % 3, b = (axis + 2) % 3;
    const bool high = (side & 1) != 0;
    const vec3 e = hi - lo;
    BoxSide out{lo, vec3(0.0f), vec3(0.0f), vec3(0.0f), e[a] * e[b]};
    out.corner[axis] = high ? hi[axis] : lo[axis];
    out.edge_u[a] = e[a];
    out.edge_v[b] = e[b];
    out.n[axis] = high ? 1.0f : -1.0f;
    return out;
}

float primitive_area(const Geometry& g, uint32_t id) {
    if (g.is_triangle(id)) {
        const uint32_t* t = &g.indices[3 * static_cast<size_t>(id)];
        return 0.5f * glm::length(glm::cross(g.positions[t[1]] - g.positions[t[0]],
                                             g.positions[t[2]] - g.positions[t[0]]));
    }
    return shape_area(g.shape(id));
}

SurfaceSample sample_triangle_primitive(const Geometry& g, uint32_t id, vec2 u, vec3 n) {
    SurfaceSample s;
    const uint32_t* t = &g.indices[3 * static_cast<size_t>(id)];
    vec2 b = sample_triangle(u);
    float b0 = 1.0f - b.x - b.y;
    s.p = b0 * g.positions[t[0]] + b.x * g.positions[t[1]] + b.y * g.positions[t[2]];
    s.n = n;
    s.at = interpolate_varyings(g.uvs, g.uvs1, g.colors, t, b);
    return s;
}

SurfaceSample sample_primitive(const Geometry& g, uint32_t id, vec2 u, float u_part) {
    SurfaceSample s;
    if (g.is_triangle(id)) {
        const uint32_t* t = &g.indices[3 * static_cast<size_t>(id)];
        vec3 n = triangle_normal(g.positions[t[0]], g.positions[t[1]], g.positions[t[2]]);
        return sample_triangle_primitive(g, id, u, n);
    }
    const AnalyticShape& shape = g.shape(id);
    if (shape.kind == ShapeKind::Quad) {
        s.p = shape.p0 + u.x * shape.p1 + u.y * shape.p2;
        s.n = shape.frame.n;
        s.at = u;
        return s;
    }
    vec3 p, n;
    int part;
    sample_shape_local(shape, u, u_part, p, n, part);
    if (shape.transformed) {
        p = vec3(shape.to_world * vec4(p, 1.0f));
        n = glm::normalize(shape.normal_to_world * n);
    }
    // shape_surface recomputes uv (and projects p onto the surface) from the point alone.
    ShapeHit at;
    at.t = 0.0f;
    at.part = part;
    ShapeSurface surface = shape_surface(shape, Ray{p, vec3(0.0f), 0.0f}, at);
    s.p = surface.p;
    s.n = n;
    s.at = surface.uv;
    return s;
}

}  // namespace svetlo
