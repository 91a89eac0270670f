#include "svetlo/geometry/shapes.h"

#include "svetlo/geometry/csg.h"
#include "svetlo/geometry/sdf.h"

namespace svetlo {

namespace {

/// Roots of a t^2 + 2 h t + c = 0 with the cancellation-free form of the discriminant
/// (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems,
/// ch. 7). Returns false when there is no real root.
bool solve_quadratic(float a, float h, float c, float discriminant, float& t0, float& t1) {
    if (discriminant < 0.0f || a == 0.0f) return false;
    float q = -h - std::copysign(std::sqrt(discriminant), h);
    t0 = c / q;
    t1 = q / a;
    if (q == 0.0f) t0 = t1;
    if (t0 > t1) std::swap(t0, t1);
    return true;
}

Ray local_ray(const AnalyticShape& s, const Ray& ray) {
    if (!s.transformed) return ray;
    return Ray{vec3(s.to_local * vec4(ray.o, 1.0f)), vec3(s.to_local * vec4(ray.d, 0.0f)),
               ray.tmax};
}

bool hit_sphere(const AnalyticShape& s, const Ray& r, float tmax, float& t) {
    vec3 oc = r.o - s.p0;
    float a = glm::dot(r.d, r.d);
    float h = glm::dot(oc, r.d);
    float c = glm::dot(oc, oc) - s.radius * s.radius;
    vec3 l = oc - (h / a) * r.d;  // centre to the ray's closest approach
    float disc = a * (s.radius * s.radius - glm::dot(l, l));
    float t0, t1;
    if (!solve_quadratic(a, h, c, disc, t0, t1)) return false;
    if (t0 > 0.0f && t0 < tmax) {
        t = t0;
        return true;
    }
    if (t1 > 0.0f && t1 < tmax) {
        t = t1;
        return true;
    }
    return false;
}

bool hit_quad(const AnalyticShape& s, const Ray& r, float tmax, float& t) {
    vec3 n = glm::cross(s.p1, s.p2);
    float dn = glm::dot(r.d, n);
    if (dn == 0.0f) return false;
    float tt = glm::dot(s.p0 - r.o, n) / dn;
    if (!(tt > 0.0f && tt < tmax)) return false;
    vec3 q = r.o + tt * r.d - s.p0;
    vec3 w = n / glm::dot(n, n);
    float alpha = glm::dot(w, glm::cross(q, s.p2));
    float beta = glm::dot(w, glm::cross(s.p1, q));
    if (alpha < 0.0f || alpha > 1.0f || beta < 0.0f || beta > 1.0f) return false;
    t = tt;
    return true;
}

bool hit_plane(const AnalyticShape& s, const Ray& r, float tmax, float& t) {
    float dn = glm::dot(r.d, s.p1);
    if (dn == 0.0f) return false;
    float tt = glm::dot(s.p0 - r.o, s.p1) / dn;
    if (!(tt > 0.0f && tt < tmax)) return false;
    t = tt;
    return true;
}

/// The slab interval of a box over the whole line, with the faces of entry and exit.
bool box_interval(const AnalyticShape& s, const Ray& r, float& t_near, int& near_face, float& t_far,
                  int& far_face) {
    t_near = -kInfinity;
    t_far = kInfinity;
    near_face = far_face = 0;
    for (int k = 0; k < 3; ++k) {
        float inv = 1.0f / r.d[k];
        float ta = (s.p0[k] - r.o[k]) * inv, tb = (s.p1[k] - r.o[k]) * inv;
        int fa = 2 * k, fb = 2 * k + 1;  // face 2k is the min side, 2k+1 the max side
        if (ta > tb) {
            std::swap(ta, tb);
            std::swap(fa, fb);
        }
        if (std::isnan(ta)) continue;  // ray parallel to and on a slab boundary
        if (ta > t_near) {
            t_near = ta;
            near_face = fa;
        }
        if (tb < t_far) {
            t_far = tb;
            far_face = fb;
        }
    }
    return t_near <= t_far;
}

bool hit_box(const AnalyticShape& s, const Ray& r, float tmax, float& t, int& part) {
    float t_near, t_far;
    int near_face, far_face;
    if (!box_interval(s, r, t_near, near_face, t_far, far_face)) return false;
    if (t_near > 0.0f && t_near < tmax) {
        t = t_near;
        part = near_face;
        return true;
    }
    if (t_far > 0.0f && t_far < tmax) {
        t = t_far;
        part = far_face;
        return true;
    }
    return false;
}

/// Every point where the line o + t d (in the shape's space) crosses the surface of a
/// cylinder (cone = false) or cone (cone = true) in its axis frame, z from 0 to h, passed to
/// `visit(t, part)` for t of any sign. Parts: 0 lateral surface, 1 base cap (z = 0), 2 top
/// cap (z = h, cylinder only).
template <class Visit>
void quadric_crossings(const AnalyticShape& s, const Ray& r, bool cone, Visit&& visit) {
    vec3 o = s.frame.to_local(r.o - s.p0), d = s.frame.to_local(r.d);
    float h = s.height, rad = s.radius;
    // The quadric's coefficients and roots in double precision. In single, the discriminant
    // b^2 - a c of a ray from afar cancels: from 10 m, a cylinder 0.38 m wide was hit 1e-5 m
    // off its wall, inside the solid beyond the offset of a shadow ray's origin, which then
    // met the same wall again (black speckles on a drilled cube's holes; the test
    // Csg.TheDrilledCubesHoleWallsAreLitWhereALightReachesThem).
    const double ox = o.x, oy = o.y, dx = d.x, dy = d.y;
    double a, b, c;
    if (!cone) {
        a = dx * dx + dy * dy;
        b = ox * dx + oy * dy;
        c = ox * ox + oy * oy - static_cast<double>(rad) * rad;
    } else {
        const double k2 = static_cast<double>(rad) * rad / (static_cast<double>(h) * h);
        const double hz = static_cast<double>(h) - o.z, dz = d.z;
        a = dx * dx + dy * dy - k2 * dz * dz;
        b = ox * dx + oy * dy + k2 * hz * dz;
        c = ox * ox + oy * oy - k2 * hz * hz;
    }
    if (std::abs(a) > 1e-12 * glm::dot(d, d)) {
        const double disc = b * b - a * c;
        if (disc >= 0.0) {
            const double q = -b - std::copysign(std::sqrt(disc), b);
            for (double root : {c / q, q / a}) {
                if (q == 0.0) root = 0.0;  // the line touches at its closest approach
                const auto tt = static_cast<float>(root);
                float z = o.z + tt * d.z;
                if (z >= 0.0f && z <= h) visit(tt, 0);
            }
        }
    } else if (cone && b != 0.0) {  // ray parallel to a generator line: one root
        const auto tt = static_cast<float>(-c / (2.0 * b));
        float z = o.z + tt * d.z;
        if (z >= 0.0f && z <= h) visit(tt, 0);
    }
    if (d.z != 0.0f) {
        for (int cap = 1; cap <= (cone ? 1 : 2); ++cap) {
            float zc = cap == 1 ? 0.0f : h;
            float tt = (zc - o.z) / d.z;
            float x = o.x + tt * d.x, y = o.y + tt * d.y;
            if (x * x + y * y <= rad * rad) visit(tt, cap);
        }
    }
}

bool hit_quadric(const AnalyticShape& s, const Ray& r, float tmax, float& t, int& part, bool cone) {
    float best = tmax;
    bool found = false;
    quadric_crossings(s, r, cone, [&](float tt, int p) {
        if (tt > 0.0f && tt < best) {
            best = tt;
            part = p;
            found = true;
        }
    });
    if (found) t = best;
    return found;
}

}  // namespace

AnalyticShape make_analytic_shape(const Shape& shape, const Transform& transform,
                                  uint32_t material) {
    AnalyticShape s;
    s.material = material;
    s.transformed = !transform.is_identity;
    s.to_world = transform.matrix;
    s.to_local = glm::inverse(transform.matrix);
    s.normal_to_world = normal_matrix(transform.matrix);
    if (const auto* sp = std::get_if<Sphere>(&shape)) {
        s.kind = ShapeKind::Sphere;
        s.p0 = sp->center;
        s.radius = sp->radius;
    } else if (const auto* q = std::get_if<Quad>(&shape)) {
        // An affine map takes a parallelogram to a parallelogram: bake it.
        s.kind = ShapeKind::Quad;
        s.p0 = transform.point(q->corner);
        s.p1 = transform.vector(q->edge_u);
        s.p2 = transform.vector(q->edge_v);
        s.frame = Frame::from_normal(glm::normalize(glm::cross(s.p1, s.p2)));
        s.transformed = false;
    } else if (const auto* pl = std::get_if<Plane>(&shape)) {
        s.kind = ShapeKind::Plane;
        s.p0 = transform.point(pl->point);
        s.p1 = glm::normalize(s.normal_to_world * pl->normal);
        s.frame = Frame::from_normal(s.p1);
        s.transformed = false;
    } else if (const auto* b = std::get_if<Box>(&shape)) {
        s.kind = ShapeKind::Box;
        s.p0 = b->min;
        s.p1 = b->max;
    } else if (const auto* cy = std::get_if<Cylinder>(&shape)) {
        s.kind = ShapeKind::Cylinder;
        s.p0 = cy->base;
        s.p1 = cy->axis;
        s.radius = cy->radius;
        s.height = glm::length(cy->axis);
        s.frame = Frame::from_normal(cy->axis / s.height);
    } else if (const auto* csg = std::get_if<Csg>(&shape)) {
        s.kind = ShapeKind::Csg;
        s.csg = std::make_shared<const CsgShape>(*csg, transform, material);
        s.transformed = false;  // the tree holds world-space leaves
    } else if (const auto* imp = std::get_if<Implicit>(&shape)) {
        s.kind = ShapeKind::Implicit;
        s.sdf = std::make_shared<const SdfShape>(imp->root, transform.matrix);
        s.transformed = false;
    } else if (const auto* co = std::get_if<Cone>(&shape)) {
        s.kind = ShapeKind::Cone;
        s.p0 = co->base;
        s.p1 = co->axis;
        s.radius = co->radius;
        s.height = glm::length(co->axis);
        s.frame = Frame::from_normal(co->axis / s.height);
    }
    return s;
}

Bounds3 shape_bounds(const AnalyticShape& s) {
    Bounds3 local;
    switch (s.kind) {
        case ShapeKind::Sphere:
            local.extend(s.p0 - vec3(s.radius));
            local.extend(s.p0 + vec3(s.radius));
            break;
        case ShapeKind::Quad:
            for (vec3 p : {s.p0, s.p0 + s.p1, s.p0 + s.p2, s.p0 + s.p1 + s.p2}) local.extend(p);
            return local;  // already world space
        case ShapeKind::Plane:
            return Bounds3{vec3(-kInfinity), vec3(kInfinity)};
        case ShapeKind::Csg:
            return s.csg->bounds();
        case ShapeKind::Implicit:
            return s.sdf->bounds();
        case ShapeKind::Box:
            local.extend(s.p0);
            local.extend(s.p1);
            break;
        case ShapeKind::Cylinder:
        case ShapeKind::Cone: {
            // A disk of radius r with unit normal a spans r sqrt(1 - a_k^2) along axis k.
            vec3 a = s.p1 / s.height;
            vec3 e = s.radius * glm::sqrt(glm::max(vec3(0.0f), vec3(1.0f) - a * a));
            for (vec3 c : {s.p0, s.p0 + s.p1}) {
                local.extend(c - e);
                local.extend(c + e);
            }
            break;
        }
    }
    if (!s.transformed) return local;
    return transformed_bounds(local, s.to_world);
}

bool intersect_shape(const AnalyticShape& s, const Ray& ray, float tmax, ShapeHit& hit) {
    hit.part = 0;
    hit.sub = 0;
    hit.u = hit.v = 0.0f;
    switch (s.kind) {
        case ShapeKind::Quad:
            return hit_quad(s, ray, tmax, hit.t);
        case ShapeKind::Plane:
            return hit_plane(s, ray, tmax, hit.t);
        case ShapeKind::Csg:
            return s.csg->intersect(ray, tmax, hit);
        case ShapeKind::Implicit:
            return s.sdf->intersect(ray, tmax, hit.t);
        default:
            break;
    }
    Ray r = local_ray(s, ray);
    switch (s.kind) {
        case ShapeKind::Sphere:
            return hit_sphere(s, r, tmax, hit.t);
        case ShapeKind::Box:
            return hit_box(s, r, tmax, hit.t, hit.part);
        case ShapeKind::Cylinder:
            return hit_quadric(s, r, tmax, hit.t, hit.part, false);
        case ShapeKind::Cone:
            return hit_quadric(s, r, tmax, hit.t, hit.part, true);
        default:
            return false;
    }
}

bool shape_interval(const AnalyticShape& s, const Ray& ray, float& t0, int& part0, float& t1,
                    int& part1) {
    Ray r = local_ray(s, ray);
    part0 = part1 = 0;
    switch (s.kind) {
        case ShapeKind::Sphere: {
            vec3 oc = r.o - s.p0;
            float a = glm::dot(r.d, r.d);
            float h = glm::dot(oc, r.d);
            float c = glm::dot(oc, oc) - s.radius * s.radius;
            vec3 l = oc - (h / a) * r.d;
            return solve_quadratic(a, h, c, a * (s.radius * s.radius - glm::dot(l, l)), t0, t1);
        }
        case ShapeKind::Box:
            return box_interval(s, r, t0, part0, t1, part1);
        case ShapeKind::Cylinder:
        case ShapeKind::Cone: {
            t0 = kInfinity;
            t1 = -kInfinity;
            quadric_crossings(s, r, s.kind == ShapeKind::Cone, [&](float t, int part) {
                if (t < t0) {
                    t0 = t;
                    part0 = part;
                }
                if (t > t1) {
                    t1 = t;
                    part1 = part;
                }
            });
            return t0 <= t1;
        }
        default:
            return false;
    }
}

bool shape_contains(const AnalyticShape& s, vec3 pw) {
    if (s.kind == ShapeKind::Csg) return s.csg->contains(pw);
    if (s.kind == ShapeKind::Implicit) return s.sdf->eval(pw) < 0.0f;
    vec3 p = s.transformed ? vec3(s.to_local * vec4(pw, 1.0f)) : pw;
    switch (s.kind) {
        case ShapeKind::Sphere:
            return glm::dot(p - s.p0, p - s.p0) < s.radius * s.radius;
        case ShapeKind::Box:
            return glm::all(glm::greaterThan(p, s.p0)) && glm::all(glm::lessThan(p, s.p1));
        case ShapeKind::Cylinder:
        case ShapeKind::Cone: {
            vec3 q = s.frame.to_local(p - s.p0);
            if (!(q.z > 0.0f && q.z < s.height)) return false;
            float r = s.kind == ShapeKind::Cylinder ? s.radius : s.radius * (1.0f - q.z / s.height);
            return q.x * q.x + q.y * q.y < r * r;
        }
        default:
            return false;
    }
}

namespace {

/// The tangent of a surface with unit normal n and texture gradients dp/du, dp/dv (any
/// lengths): dp/du's unit direction and the side dp/dv lies on (Mesh::tangents); zero where
/// dp/du vanishes (a pole).
vec4 surface_tangent(vec3 n, vec3 dpdu, vec3 dpdv) {
    const float len = glm::length(dpdu);
    if (!(len > 0.0f)) return vec4(0.0f);
    const vec3 t = dpdu / len;
    return vec4(t, glm::dot(glm::cross(n, t), dpdv) < 0.0f ? -1.0f : 1.0f);
}

/// A cylinder's or cone's surface at p (object space; moved onto a cap's plane for parts 1
/// and 2): its normal, uv and the directions of dp/du and dp/dv.
inline void quadric_surface(const AnalyticShape& s, int part, vec3& p, vec3& n, vec2& uv,
                            vec3& dpdu, vec3& dpdv) {
    vec3 q = s.frame.to_local(p - s.p0);
    float phi = std::atan2(q.y, q.x);
    if (part == 0) {
        float z = std::clamp(q.z, 0.0f, s.height);
        vec3 ln;
        if (s.kind == ShapeKind::Cylinder) {
            ln = vec3(q.x, q.y, 0.0f);
        } else {
            float k2 = square(s.radius / s.height);
            ln = vec3(q.x, q.y, k2 * (s.height - z));
        }
        n = s.frame.to_world(glm::normalize(ln));
        uv = vec2(0.5f + phi / (2.0f * kPi), z / s.height);
        dpdu = s.frame.to_world(vec3(-q.y, q.x, 0.0f));
        dpdv = s.frame.n;
    } else {
        n = part == 1 ? -s.frame.n : s.frame.n;
        p = p - glm::dot(p - (part == 1 ? s.p0 : s.p0 + s.p1), s.frame.n) * s.frame.n;
        uv = vec2(0.5f + 0.5f * q.x / s.radius, 0.5f + 0.5f * q.y / s.radius);
        dpdu = s.frame.t;
        dpdv = s.frame.b;
    }
}

ShapeSurface analytic_surface(const AnalyticShape& s, const Ray& ray, float t, int part) {
    ShapeSurface out;
    vec3 pw = ray.o + t * ray.d;
    if (s.kind == ShapeKind::Quad) {
        vec3 n = glm::cross(s.p1, s.p2);
        vec3 w = n / glm::dot(n, n), q = pw - s.p0;
        out.uv = vec2(glm::dot(w, glm::cross(q, s.p2)), glm::dot(w, glm::cross(s.p1, q)));
        out.p = s.p0 + out.uv.x * s.p1 + out.uv.y * s.p2;
        out.n = s.frame.n;
        out.tangent = surface_tangent(out.n, s.p1, s.p2);
        return out;
    }
    if (s.kind == ShapeKind::Plane) {
        vec3 q = pw - s.p0;
        out.p = pw - glm::dot(q, s.p1) * s.p1;  // back onto the plane
        out.uv = vec2(glm::dot(q, s.frame.t), glm::dot(q, s.frame.b));
        out.n = s.p1;
        out.tangent = surface_tangent(out.n, s.frame.t, s.frame.b);
        return out;
    }
    vec3 p = s.transformed ? vec3(s.to_local * vec4(pw, 1.0f)) : pw;
    vec3 n(0.0f);
    vec3 dpdu(0.0f), dpdv(0.0f);  // object space, directions only
    switch (s.kind) {
        case ShapeKind::Sphere: {
            vec3 q = glm::normalize(p - s.p0);
            p = s.p0 + s.radius * q;  // back onto the sphere
            n = q;
            // u: longitude about +y from +z toward +x; v: latitude from the south pole.
            out.uv = vec2(0.5f + std::atan2(q.x, q.z) / (2.0f * kPi),
                          0.5f + std::asin(std::clamp(q.y, -1.0f, 1.0f)) / kPi);
            dpdu = vec3(q.z, 0.0f, -q.x);  // along the parallel, toward +x from +z
            dpdv = glm::cross(q, dpdu);    // up the meridian
            break;
        }
        case ShapeKind::Box: {
            int axis = part / 2;
            p[axis] = (part & 1) ? s.p1[axis] : s.p0[axis];  // onto the face
            n[axis] = (part & 1) ? 1.0f : -1.0f;
            int a = (axis + 1) % 3, b = (axis + 2) % 3;
            vec3 e = s.p1 - s.p0;
            out.uv = vec2((p[a] - s.p0[a]) / e[a], (p[b] - s.p0[b]) / e[b]);
            dpdu[a] = 1.0f;
            dpdv[b] = 1.0f;
            break;
        }
        default:  // cylinder, cone
            quadric_surface(s, part, p, n, out.uv, dpdu, dpdv);
            break;
    }
    if (s.transformed) {
        out.p = vec3(s.to_world * vec4(p, 1.0f));
        out.n = glm::normalize(s.normal_to_world * n);
        dpdu = mat3(s.to_world) * dpdu;
        dpdv = mat3(s.to_world) * dpdv;
    } else {
        out.p = p;
        out.n = n;
    }
    out.tangent = surface_tangent(out.n, dpdu, dpdv);
    return out;
}

}  // namespace

ShapeSurface shape_surface(const AnalyticShape& s, const Ray& ray, const ShapeHit& hit) {
    ShapeSurface out;
    switch (s.kind) {
        case ShapeKind::Csg:
            return s.csg->surface(ray, hit);
        case ShapeKind::Implicit:
            out = s.sdf->surface(ray, hit.t);
            out.material = s.material;
            return out;
        default:
            out = analytic_surface(s, ray, hit.t, hit.part);
            out.ns = out.n;
            out.material = s.material;
            return out;
    }
}

float shape_area(const AnalyticShape& s) {
    float scale2 = 1.0f;  // area scale of a similarity transform
    if (s.transformed) scale2 = std::pow(std::abs(glm::determinant(mat3(s.to_world))), 2.0f / 3.0f);
    switch (s.kind) {
        case ShapeKind::Sphere:
            return scale2 * 4.0f * kPi * s.radius * s.radius;
        case ShapeKind::Quad:
            return glm::length(glm::cross(s.p1, s.p2));
        case ShapeKind::Plane:
            return kInfinity;
        case ShapeKind::Box: {
            vec3 e = s.p1 - s.p0;
            return scale2 * 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
        }
        case ShapeKind::Cylinder:
            return scale2 * (2.0f * kPi * s.radius * s.height + 2.0f * kPi * s.radius * s.radius);
        case ShapeKind::Cone:
            return scale2 * (kPi * s.radius * std::sqrt(s.radius * s.radius + s.height * s.height) +
                             kPi * s.radius * s.radius);
        case ShapeKind::Csg:
        case ShapeKind::Implicit:
            return 0.0f;  // not sampled as lights
    }
    return 0.0f;
}

}  // namespace svetlo
