// What the BSDF tests share: no textures, the shading normal +z, directions by angles.
#pragma once

#include <vector>

#include "svetlo/shading/bsdf.h"

namespace svetlo {

inline const std::vector<TextureImage> kNoTextures;
inline const vec3 kN(0.0f, 0.0f, 1.0f);

/// The unit direction at polar angle theta from +z and azimuth phi from +x, in degrees.
inline vec3 dir(float theta_deg, float phi_deg) {
    float t = radians(theta_deg), p = radians(phi_deg);
    return vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

}  // namespace svetlo
