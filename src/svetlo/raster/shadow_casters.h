// What the rasterizer's shadow techniques cast shadows from: each delta light is one caster,
// and each light with area (an area light or an emissive object) is split into N point
// casters spread over it by area, the lecture's approximation of an area light by point
// lights. A light's visibility V at a sample is the mean, over the casters of that light
// that the sample faces, of what each technique says of it (0 shadowed, 1 lit, or between
// for a filter); 1 where the sample faces none (docs/cli.md: the visibility AOV).
#pragma once

#include <vector>

#include "svetlo/shading/light_set.h"

namespace svetlo {

struct ShadowCaster {
    enum class Kind { Point, Spot, Directional };
    Kind kind = Kind::Point;
    uint32_t source = 0;      // its light's row of the light set (LightVisibility)
    vec3 position{0.0f};      // point and spot (m)
    vec3 direction{0.0f};     // unit: a spot's axis, or the way a directional light travels
    vec3 normal{0.0f};        // the emitting side of a point on a light with area, else zero
    float cos_outer = -1.0f;  // a spot's cone: cos of its outer half-angle
    float size = 0.0f;        // the width of the light it stands for (m), for PCSS; 0 if delta

    /// The unit direction from p toward the caster.
    vec3 to_light(vec3 p) const {
        return kind == Kind::Directional ? -direction : glm::normalize(position - p);
    }
    /// Whether light from the caster reaches a surface at p with unit normal n (the side the
    /// camera sees) from the front: n faces it, and a point of an emitter faces p.
    /// (Both tests made, without a branch: a frame asks it of every sample it shadows.)
    bool faces(vec3 p, vec3 n) const {
        vec3 wi = kind == Kind::Directional ? -direction : position - p;  // (signs only)
        return static_cast<bool>(static_cast<int>(glm::dot(n, wi) > 0.0f) &
                                 static_cast<int>(!(glm::dot(normal, wi) > 0.0f)));
    }
};

/// The casters of every source of `lights`, grouped by source in its order. A light with area
/// becomes `points_per_area` point casters (stratified over its area, each moved off its
/// surface by `lift` metres so that the emitter's own surface lies behind it), or, when
/// `points_per_area` is 0, one caster at its centroid with `size` the square root of its area
/// (for PCSS).
std::vector<ShadowCaster> shadow_casters(const Scene& scene, const LightSet& lights,
                                         int points_per_area, float lift);

/// The same for given points on the lights with area (the raytraced technique casts from the
/// rasterizer's own VPLs, so that its shadows weigh the very points the shading sums).
std::vector<ShadowCaster> shadow_casters(const Scene& scene, const LightSet& lights,
                                         const std::vector<std::vector<AreaPoint>>& points);

}  // namespace svetlo
