// Direct illumination from punctual lights (point, directional, spot): for a point p, the
// direction to the light, its distance and the irradiance a surface facing the light would
// get there. A surface with normal n then receives E = irradiance * max(0, n.wi).
#pragma once

#include "svetlo/scene/scene.h"

namespace svetlo {

struct PunctualSample {
    vec3 wi{0.0f};               // unit, from p toward the light
    float distance = kInfinity;  // to the light (infinite for a directional light)
    Color irradiance{0.0f};      // W/m^2 on a surface facing the light, before occlusion
};

/// Smooth cone factor of a spot light for the direction from the light to the point:
/// 1 inside the inner half-angle, 0 outside the outer one, and between them the Hermite
/// smoothstep of cos(theta) from cos(outer) to cos(inner).
float spot_cone_factor(const SpotLight& light, vec3 light_to_point);

/// Requires a point, directional or spot light.
PunctualSample sample_punctual(const Light& light, vec3 p);

}  // namespace svetlo
