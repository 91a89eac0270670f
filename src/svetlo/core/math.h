// Vector types and small helpers shared by every module. Geometry and radiance are single
// precision (glm::vec3); accumulators that sum many samples use double where it matters.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

namespace svetlo {

using glm::mat2;
using glm::mat3;
using glm::mat4;
using glm::vec2;
using glm::vec3;
using glm::vec4;

/// Linear RGB radiance, irradiance or reflectance, depending on context.
using Color = glm::vec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

inline float radians(float degrees) { return degrees * (kPi / 180.0f); }
inline float max_component(vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float min_component(vec3 v) { return std::min(v.x, std::min(v.y, v.z)); }
inline int max_dimension(vec3 v) { return v.x > v.y ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2); }
/// The inverse transpose of a transform's linear part: it carries normals.
inline mat3 normal_matrix(const mat4& m) { return glm::transpose(glm::inverse(mat3(m))); }

/// The unit normal of the counter-clockwise side of triangle (a, b, c). In double precision
/// when the float cross product overflows (a triangle wider than about 1e19 units), so that
/// every triangle a float can hold has a finite normal; (0, 0, 1) for a triangle of no area.
inline vec3 triangle_normal(vec3 a, vec3 b, vec3 c) {
    vec3 n = glm::cross(b - a, c - a);
    float len2 = glm::dot(n, n);
    if (len2 > 0.0f && std::isfinite(len2))
        return n * (1.0f / std::sqrt(len2));  // as glm::normalize
    glm::dvec3 da(a), db(b), dc(c);
    glm::dvec3 dn = glm::cross(db - da, dc - da);
    double dlen = glm::length(dn);
    return dlen > 0.0 && std::isfinite(dlen) ? vec3(dn / dlen) : vec3(0.0f, 0.0f, 1.0f);
}

/// True when every channel is a finite number (no NaN, no infinity).
inline bool is_finite(Color c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}
inline bool is_finite(glm::vec4 v) { return is_finite(Color(v)) && std::isfinite(v.w); }

inline float luminance(Color c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }
inline bool is_black(Color c) { return c.r == 0.0f && c.g == 0.0f && c.b == 0.0f; }
inline float square(float x) { return x * x; }
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }

/// atan2(y, x) in radians, within 3e-7 of the exact angle (tests/core/math_test.cpp), at a
/// fraction of libm's cost: the octant folded onto [0, 1] by min(|x|, |y|) / max(|x|, |y|),
/// where atan(a) = a P(a^2), P of degree 7 in a^2, fitted near-minimax to atan on [0, 1]
/// (Lawson's iteration; largest error 1.4e-7 in float). The signs and quadrants are
/// std::atan2's; atan2(0, 0) gives 0 for either zero's sign. The environment map's lookup
/// reads each direction through it (shading/environment.cpp).
inline float atan2_approx(float y, float x) {
    const float ax = std::abs(x), ay = std::abs(y);
    const float hi = std::max(ax, ay), lo = std::min(ax, ay);
    const float a = hi > 0.0f ? lo / hi : 0.0f, s = a * a;
    float p = -0.004054566845f;
    p = p * s + 0.02186295763f;
    p = p * s - 0.05591232702f;
    p = p * s + 0.09642197192f;
    p = p * s - 0.1390862912f;
    p = p * s + 0.1994656622f;
    p = p * s - 0.3332985938f;
    p = p * s + 0.9999993443f;
    // Selects, not branches: a loop over many directions vectorizes (Environment::radiance_many).
    float r = a * p;
    r = ay > ax ? 0.5f * kPi - r : r;
    r = x < 0.0f ? kPi - r : r;
    return std::copysign(r, y);
}

/// An orthonormal basis (t, b, n) around a unit normal n, without branches on the normal's
/// direction. Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
struct Frame {
    vec3 t, b, n;

    static Frame from_normal(vec3 n) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        return {vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x),
                vec3(b, sign + n.y * n.y * a, -n.y), n};
    }
    vec3 to_local(vec3 v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
    vec3 to_world(vec3 v) const { return v.x * t + v.y * b + v.z * n; }
};

/// An axis-aligned bounding box in world space. Empty when min > max.
struct Bounds3 {
    vec3 min{kInfinity};
    vec3 max{-kInfinity};

    void extend(vec3 p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Bounds3& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    vec3 extent() const { return max - min; }
    vec3 center() const { return 0.5f * (min + max); }
    float surface_area() const {
        if (empty()) return 0.0f;
        vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
};

/// The box around `b`'s eight corners carried by the affine map m (empty stays empty).
inline Bounds3 transformed_bounds(const Bounds3& b, const mat4& m) {
    Bounds3 out;
    if (b.empty()) return out;
    for (int k = 0; k < 8; ++k) {
        const vec3 corner((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                          (k & 4) ? b.max.z : b.min.z);
        out.extend(vec3(m * vec4(corner, 1.0f)));
    }
    return out;
}

}  // namespace svetlo
