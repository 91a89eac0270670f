// Ray against axis-aligned boxes, shared by every acceleration structure.
#pragma once

#include <cmath>

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
