// Rays and hits in world space. Directions need not be unit length: t is measured in units of
// |d|, which lets transformed shapes intersect object-space rays with the same t.
#pragma once

#include <cstdint>

#include "svetlo/core/bit_cast.h"
#include "svetlo/core/math.h"

namespace svetlo {

struct Ray {
    vec3 o{0.0f};
    vec3 d{0.0f, 0.0f, 1.0f};
    float tmax = kInfinity;
};

struct Hit {
    float t = kInfinity;
    uint32_t prim = ~0u;       // primitive id (see Geometry)
    float u = 0.0f, v = 0.0f;  // barycentrics of vertices 1 and 2 for triangles
    int part = 0;              // which face or surface of an analytic shape
    uint32_t sub = 0;          // the leaf of a CSG shape (see ShapeHit)
    // The placement (Geometry::placements) whose prototype `prim` belongs to; kNone for the
    // world's own primitives.
    uint32_t instance = kNone;
    static constexpr uint32_t kNone = ~0u;
    bool valid() const { return prim != ~0u; }
};

/// Moves a surface point off the surface along the geometric normal, toward the side that `w`
/// leaves into, by a few ULPs of its coordinates, so that rays leaving it do not hit the same
/// surface again. Wächter and Binder, "A Fast and Robust Method for Avoiding
/// Self-Intersection", Ray Tracing Gems, ch. 6 (2019).
inline vec3 offset_ray_origin(vec3 p, vec3 ng, vec3 w) {
    constexpr float kOrigin = 1.0f / 32.0f;         // below this magnitude use a fixed offset
    constexpr float kFloatScale = 1.0f / 65536.0f;  // that fixed offset, in scene units
    constexpr float kIntScale = 256.0f;             // ULPs per unit of normal
    vec3 n = glm::dot(ng, w) < 0.0f ? -ng : ng;
    vec3 out;
    for (int k = 0; k < 3; ++k) {
        auto of = static_cast<int32_t>(kIntScale * n[k]);
        int32_t bits = svetlo::bit_cast<int32_t>(p[k]);
        float moved = svetlo::bit_cast<float>(bits + (p[k] < 0.0f ? -of : of));
        out[k] = std::abs(p[k]) < kOrigin ? p[k] + kFloatScale * n[k] : moved;
    }
    return out;
}

/// Per-ray constants of the watertight ray-triangle test (Woop, Benthin and Wald,
/// "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013): the axis of largest |d| becomes
/// z, and a shear maps the ray onto +z.
struct RayPrecomputed {
    int kx, ky, kz;
    float sx, sy, sz;

    RayPrecomputed() = default;  // (for arrays filled ray by ray)
    explicit RayPrecomputed(const Ray& ray) {
        kz = max_dimension(glm::abs(ray.d));
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (ray.d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding
        sx = ray.d[kx] / ray.d[kz];
        sy = ray.d[ky] / ray.d[kz];
        sz = 1.0f / ray.d[kz];
    }
};

}  // namespace svetlo
