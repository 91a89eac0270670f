// Ray against axis-aligned boxes, shared by every acceleration structure.
#pragma once

#include <cmath>
#include <cstdint>

#include "svetlo/core/bit_cast.h"
#include "svetlo/geometry/ray.h"

namespace svetlo {

/// 1 + 2 gamma(3): the exit distance of a slab test is enlarged by this factor to cover the
/// rounding of (bound - o) * inv_d (pbrt-v4, section 6.8.2), so no box a ray touches is missed.
inline constexpr float kSlabRobust = 1.0f + 2.0f * 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f);

/// 1/d with zero components replaced by a huge finite value of the same sign, so that the
/// slab test never computes 0 * infinity.
inline vec3 safe_inverse(vec3 d) {
    vec3 inv;
    for (int k = 0; k < 3; ++k) inv[k] = d[k] != 0.0f ? 1.0f / d[k] : std::copysign(1e32f, d[k]);
    return inv;
}

/// The next float above x (below, with `up` false); infinities and NaN as they are.
inline float next_float(float x, bool up) {
    if (!std::isfinite(x)) return x;
    if (x == 0.0f) return up ? 0x1p-149f : -0x1p-149f;
    const auto bits = svetlo::bit_cast<int32_t>(x);
    return svetlo::bit_cast<float>((x > 0.0f) == up ? bits + 1 : bits - 1);
}

/// The box [lo, hi] moved out by one ulp on every side, as every structure stores its boxes.
/// A tight box fails a ray whose direction has a zero component and whose origin lies on the
/// box's far plane in that axis: the slab's exit (hi - o) / d is 0 * 1e32 = 0 (safe_inverse),
/// though the ray runs along the face and may meet a triangle's edge in it (a tessellated
/// piece's pole in an axis plane, a cube's edge met along its top face). Moved out, such an
/// origin lies strictly inside the slab.
inline void widen_box(vec3& lo, vec3& hi) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = next_float(lo[a], false);
        hi[a] = next_float(hi[a], true);
    }
}

/// The parametric range [t0, t1] of the ray inside the box, clipped to [0, tmax]. Returns
/// false when the ray misses the box in that range.
inline bool ray_box(vec3 lo, vec3 hi, vec3 o, vec3 inv_d, float tmax, float& t0, float& t1) {
    vec3 ta = (lo - o) * inv_d, tb = (hi - o) * inv_d;
    vec3 tn = glm::min(ta, tb), tf = glm::max(ta, tb);
    t0 = std::max(std::max(tn.x, tn.y), std::max(tn.z, 0.0f));
    t1 = std::min(std::min(tf.x, tf.y), std::min(tf.z, tmax)) * kSlabRobust;
    return t0 <= t1;
}

/// Entry distance into the box, or infinity on a miss.
inline float box_entry(vec3 lo, vec3 hi, vec3 o, vec3 inv_d, float tmax) {
    float t0, t1;
    return ray_box(lo, hi, o, inv_d, tmax, t0, t1) ? t0 : kInfinity;
}

}  // namespace svetlo
