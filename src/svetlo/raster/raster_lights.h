// Lighting for the rasterizer: the same BRDFs and punctual lights as the ray tracer, without
// occlusion (shadows are the shadow issue's). Area lights and emissive objects become sets of
// virtual point lights (VPLs): kVplsPerEmitter points placed over the emitter in proportion
// to area, each carrying radiance x area / count and emitting with a cosine from its front
// side; summed, they give the unoccluded irradiance of the emitter by quadrature.
#pragma once

#include <vector>

#include "svetlo/scene/scene.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

struct VirtualLight {
    vec3 p{0.0f}, n{0.0f};   // position and unit front normal
    Color power{0.0f};       // radiance x area represented (W/sr per unit cos, i.e. L A)
    float min_dist2 = 0.0f;  // d^2 is clamped to this (area per VPL) near the emitter
};

inline constexpr int kVplsPerEmitter = 64;

/// Emitting triangles of one object (world space), for VPL placement.
struct EmitterTriangles {
    std::vector<vec3> p;  // 3 per triangle
    std::vector<Color> radiance;
};

/// VPLs for an area light.
std::vector<VirtualLight> area_light_vpls(const AreaLight& light);
/// VPLs over the emissive triangles of one object.
std::vector<VirtualLight> triangle_vpls(const EmitterTriangles& tris);

struct RasterLights {
    std::vector<const Light*> punctual;  // point, directional, spot
    std::vector<VirtualLight> vpls;
};

/// Outgoing radiance toward wo at p: emission (front side), the ambient term, direct light
/// from every light, and for mirrors and glass the uniform environment `background`.
Color shade_point(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                  const RasterLights& lights, Color ambient, Color background);

}  // namespace svetlo
