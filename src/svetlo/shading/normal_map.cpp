#include "svetlo/shading/normal_map.h"

#include <cmath>

namespace svetlo {

vec3 mapped_normal(const NormalMap& map, Color texel, vec3 ns, vec3 ng, vec4 tangent) {
    if (!map.present() || tangent.w == 0.0f) return ns;
    // glTF: normalize((texel * 2 - 1) * (scale, scale, 1)).
    const vec3 local = (2.0f * texel - vec3(1.0f)) * vec3(map.scale, map.scale, 1.0f);
    const vec3 t(tangent);
    const vec3 b = tangent.w * glm::cross(ns, t);
    vec3 n = local.x * t + local.y * b + local.z * ns;
    const float len2 = glm::dot(n, n);
    if (!(len2 > 0.0f) || !std::isfinite(len2)) return ns;
    n /= std::sqrt(len2);
    constexpr float kMinAbove = 0.01f;  // the least cosine between the mapped and ng
    const float above = glm::dot(n, ng);
    if (above < kMinAbove) {
        // Along the great circle through n and ng, to the point kMinAbove above the plane.
        const vec3 in_plane = n - above * ng;
        const float len = glm::length(in_plane);
        if (!(len > 0.0f)) return ng;
        n = in_plane * (std::sqrt(1.0f - kMinAbove * kMinAbove) / len) + kMinAbove * ng;
    }
    return n;
}

}  // namespace svetlo
