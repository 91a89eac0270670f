#include "svetlo/geometry/sdf.h"

#include <algorithm>

#include "svetlo/geometry/ray_box.h"

namespace svetlo {

namespace {

constexpr int kMaxSteps = 2048;    // sphere-tracing steps before giving up (grazing rays)
constexpr int kBisections = 40;    // refinement of a bracketed crossing
constexpr float kMinStep = 1e-5f;  // relative to scale_: the smallest advance

/// Largest singular value of a 3x3 matrix: sqrt of the largest eigenvalue of A^T A by power
/// iteration (converges fast for the well-conditioned maps of a scene).
float spectral_norm(const mat3& a) {
    mat3 g = glm::transpose(a) * a;
    vec3 v = glm::normalize(vec3(1.0f, 0.7f, 0.3f));
    float lambda = 0.0f;
    for (int k = 0; k < 64; ++k) {
        vec3 w = g * v;
        float len = glm::length(w);
        if (!(len > 0.0f)) return 0.0f;
        v = w / len;
        lambda = len;
    }
    // Power iteration approaches from below: pad by a little to stay conservative.
    return std::sqrt(lambda) * 1.0001f;
}

/// Polynomial smooth minimum of radius k (Quilez, "smooth minimum", 2013); k = 0 is min.
float smooth_min(float a, float b, float k) {
    if (k <= 0.0f) return std::min(a, b);
    float h = std::max(k - std::abs(a - b), 0.0f) / k;
    return std::min(a, b) - h * h * k * 0.25f;
}
float smooth_max(float a, float b, float k) { return -smooth_min(-a, -b, k); }

float box_distance(vec3 p, vec3 lo, vec3 hi, float round) {
    vec3 c = 0.5f * (lo + hi), h = 0.5f * (hi - lo) - vec3(round);
    vec3 q = glm::abs(p - c) - h;
    return glm::length(glm::max(q, vec3(0.0f))) + std::min(max_component(q), 0.0f) - round;
}

/// A capped cylinder from `base` along `axis` (Quilez's "capped cylinder - arbitrary").
float cylinder_distance(vec3 p, vec3 base, vec3 axis, float r) {
    float h = glm::length(axis);
    vec3 n = axis / h;
    vec3 q = p - base;
    float along = glm::dot(q, n);
    float radial = glm::length(q - along * n);
    vec2 d(radial - r, std::abs(along - 0.5f * h) - 0.5f * h);
    return std::min(std::max(d.x, d.y), 0.0f) + glm::length(glm::max(d, vec2(0.0f)));
}

Bounds3 transform_bounds(const Bounds3& b, const mat4& m) {
    if (!std::isfinite(b.min.x + b.min.y + b.min.z + b.max.x + b.max.y + b.max.z)) {
        return Bounds3{vec3(-kInfinity), vec3(kInfinity)};
    }
    Bounds3 out;
    for (int k = 0; k < 8; ++k) {
        vec3 c((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
               (k & 4) ? b.max.z : b.min.z);
        out.extend(vec3(m * vec4(c, 1.0f)));
    }
    return out;
}

Bounds3 grow(Bounds3 b, float r) {
    b.min -= vec3(r);
    b.max += vec3(r);
    return b;
}

}  // namespace

SdfShape::SdfShape(const SdfNode& root, const mat4& to_world) {
    flatten(root, to_world * root.transform);
    bounds_ = node_bounds(0);
    vec3 e = bounds_.extent();
    const bool finite = std::isfinite(e.x + e.y + e.z);
    scale_ = finite && glm::length(e) > 0.0f ? glm::length(e) : 1.0f;
    // A few of the march's smallest steps of room: a surface that touches its bounds (a
    // sphere's poles) is crossed inside them, not at the point where the march stops. A ray
    // leaving a sphere through a pole stepped past the box's exit and missed the crossing
    // (the test Implicit.ARayStartingJustInsideFindsItsExit).
    if (finite) {
        bounds_.min -= vec3(4.0f * kMinStep * scale_);
        bounds_.max += vec3(4.0f * kMinStep * scale_);
    }
}

uint32_t SdfShape::flatten(const SdfNode& n, const mat4& to_parent) {
    auto index = static_cast<uint32_t>(nodes_.size());
    Node node{};
    node.op = n.op;
    node.a = n.a;
    node.b = n.b;
    node.r1 = n.r1;
    node.r2 = n.r2;
    node.smooth = n.smooth;
    node.transformed = to_parent != mat4(1.0f);
    node.to_parent = to_parent;
    node.to_local = glm::inverse(to_parent);
    node.inv_lipschitz = node.transformed ? 1.0f / spectral_norm(mat3(node.to_local)) : 1.0f;
    nodes_.push_back(node);
    std::vector<uint32_t> kids;
    for (const SdfNode& c : n.children) kids.push_back(flatten(c, c.transform));
    nodes_[index].first = static_cast<uint32_t>(child_index_.size());
    nodes_[index].count = static_cast<uint32_t>(kids.size());
    child_index_.insert(child_index_.end(), kids.begin(), kids.end());
    return index;
}

float SdfShape::eval_node(uint32_t k, vec3 pw) const {
    const Node& n = nodes_[k];
    vec3 p = n.transformed ? vec3(n.to_local * vec4(pw, 1.0f)) : pw;
    float d = 0.0f;
    switch (n.op) {
        case SdfOp::Sphere:
            d = glm::length(p - n.a) - n.r1;
            break;
        case SdfOp::Box:
            d = box_distance(p, n.a, n.b, 0.0f);
            break;
        case SdfOp::RoundedBox:
            d = box_distance(p, n.a, n.b, n.r1);
            break;
        case SdfOp::Torus: {
            vec3 q = p - n.a;
            vec2 t(glm::length(vec2(q.x, q.z)) - n.r1, q.y);
            d = glm::length(t) - n.r2;
            break;
        }
        case SdfOp::Cylinder:
            d = cylinder_distance(p, n.a, n.b, n.r1);
            break;
        case SdfOp::Plane:
            d = glm::dot(p - n.a, n.b);
            break;
        case SdfOp::Union:
        case SdfOp::Intersection:
        case SdfOp::Difference: {
            d = eval_node(child_index_[n.first], p);
            for (uint32_t c = 1; c < n.count; ++c) {
                float e = eval_node(child_index_[n.first + c], p);
                if (n.op == SdfOp::Union)
                    d = smooth_min(d, e, n.smooth);
                else if (n.op == SdfOp::Intersection)
                    d = smooth_max(d, e, n.smooth);
                else
                    d = smooth_max(d, -e, n.smooth);
            }
            break;
        }
    }
    return d * n.inv_lipschitz;
}

Bounds3 SdfShape::node_bounds(uint32_t k) const {
    const Node& n = nodes_[k];
    Bounds3 b;
    switch (n.op) {
        case SdfOp::Sphere:
            b = Bounds3{n.a - vec3(n.r1), n.a + vec3(n.r1)};
            break;
        case SdfOp::Box:
        case SdfOp::RoundedBox:
            b = Bounds3{n.a, n.b};
            break;
        case SdfOp::Torus: {
            vec3 e(n.r1 + n.r2, n.r2, n.r1 + n.r2);
            b = Bounds3{n.a - e, n.a + e};
            break;
        }
        case SdfOp::Cylinder: {
            vec3 a = n.b / glm::length(n.b);
            vec3 e = n.r1 * glm::sqrt(glm::max(vec3(0.0f), vec3(1.0f) - a * a));
            for (vec3 c : {n.a, n.a + n.b}) {
                b.extend(c - e);
                b.extend(c + e);
            }
            break;
        }
        case SdfOp::Plane:
            b = Bounds3{vec3(-kInfinity), vec3(kInfinity)};
            break;
        case SdfOp::Union:
        case SdfOp::Intersection:
        case SdfOp::Difference: {
            b = node_bounds(child_index_[n.first]);
            for (uint32_t c = 1; c < n.count && n.op != SdfOp::Difference; ++c) {
                Bounds3 cb = node_bounds(child_index_[n.first + c]);
                if (n.op == SdfOp::Union) {
                    b.extend(cb);
                } else {
                    b.min = glm::max(b.min, cb.min);
                    b.max = glm::min(b.max, cb.max);
                }
            }
            // A smooth blend moves the surface out by at most smooth / 4.
            if (n.smooth > 0.0f) b = grow(b, n.smooth);
            if (glm::any(glm::greaterThan(b.min, b.max)))
                b = Bounds3{vec3(0.0f), vec3(0.0f)};  // empty
            break;
        }
    }
    return n.transformed ? transform_bounds(b, n.to_parent) : b;
}

vec3 SdfShape::normal(vec3 p) const {
    float h = 1e-4f * scale_ + 1e-6f * max_component(glm::abs(p));
    vec3 g(eval(p + vec3(h, 0, 0)) - eval(p - vec3(h, 0, 0)),
           eval(p + vec3(0, h, 0)) - eval(p - vec3(0, h, 0)),
           eval(p + vec3(0, 0, h)) - eval(p - vec3(0, 0, h)));
    float len = glm::length(g);
    return len > 0.0f ? g / len : vec3(0.0f, 1.0f, 0.0f);
}

bool SdfShape::intersect(const Ray& ray, float tmax, float& t_hit) const {
    float len = glm::length(ray.d);
    if (!(len > 0.0f)) return false;
    float t0 = 0.0f, t1 = tmax;
    if (std::isfinite(bounds_.min.x + bounds_.max.x + bounds_.min.y + bounds_.max.y +
                      bounds_.min.z + bounds_.max.z)) {
        if (!ray_box(bounds_.min, bounds_.max, ray.o, safe_inverse(ray.d), tmax, t0, t1))
            return false;
        t1 = std::min(t1, tmax);
    }
    float min_step = kMinStep * scale_ / len;  // in units of t
    float t = t0;
    float f = eval(ray.o + t * ray.d);
    // The side the ray travels in: outside (+1) looking for an entry, or inside (-1) looking
    // for an exit. A start on the surface itself (a secondary ray) takes the side it heads to.
    float side;
    if (t0 > 0.0f) {
        // The origin is outside the bounds, so outside the solid.
        side = 1.0f;
        if (f <= 0.0f) {  // the surface touches the bounds where the ray enters them
            t_hit = t0;
            return t0 < tmax;
        }
    } else if (std::abs(f) > min_step * len) {
        side = f > 0.0f ? 1.0f : -1.0f;
    } else {
        side = glm::dot(normal(ray.o + t * ray.d), ray.d) > 0.0f ? 1.0f : -1.0f;
        t += 2.0f * min_step;
        f = eval(ray.o + t * ray.d);
        if (f * side <= 0.0f) return false;  // grazing the start surface: nothing to find
    }
    for (int step = 0; step < kMaxSteps; ++step) {
        float t_prev = t;
        t += std::max(side * f / len, min_step);
        if (t > t1) return false;
        f = eval(ray.o + t * ray.d);
        if (f * side > 0.0f) continue;
        // Bracketed: t_prev on the ray's side, t across. Bisect to float precision.
        float lo = t_prev, hi = t;
        for (int k = 0; k < kBisections && lo < hi; ++k) {
            float mid = 0.5f * (lo + hi);
            if (mid <= lo || mid >= hi) break;
            if (eval(ray.o + mid * ray.d) * side > 0.0f)
                lo = mid;
            else
                hi = mid;
        }
        if (!(lo > 0.0f && lo < tmax)) return false;
        t_hit = lo;
        return true;
    }
    return false;
}

ShapeSurface SdfShape::surface(const Ray& ray, float t) const {
    ShapeSurface s;
    s.p = ray.o + t * ray.d;
    s.n = s.ns = normal(s.p);
    // Spherical coordinates about the centre of the bounds, as for a sphere.
    vec3 c = std::isfinite(bounds_.min.x + bounds_.max.x) ? 0.5f * (bounds_.min + bounds_.max)
                                                          : vec3(0.0f);
    vec3 q = s.p - c;
    float r = glm::length(q);
    q = r > 0.0f ? q / r : vec3(0.0f, 1.0f, 0.0f);
    s.uv = vec2(0.5f + std::atan2(q.x, q.z) / (2.0f * kPi),
                0.5f + std::asin(std::clamp(q.y, -1.0f, 1.0f)) / kPi);
    s.material = 0;
    return s;
}

}  // namespace svetlo
