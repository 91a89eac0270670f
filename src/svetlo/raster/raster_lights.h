// Lighting for the rasterizer: the light set (shading/light_set.h) and the direct-light sum
// (shading/direct_light.h) of every engine, with the visibility the rasterizer knows (each
// light's mask from the shadow technique, shadow_masks.h). Lights with area are sampled at
// render.area_light_points fixed points (64 by default), virtual point lights (VPLs): a
// low-discrepancy set over the emitter by area, the same in every frame and pixel, so the
// image has no noise; near a VPL, d^2 is clamped to the area it stands for.
#pragma once

#include <vector>

#include "svetlo/raster/image_based_lighting.h"
#include "svetlo/raster/simd_shading.h"
#include "svetlo/scene/scene.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/light_set.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

struct RasterLights {
    /// `threads` make the environment's prefiltered levels (0: all cores).
    /// `ibl`, when given, keeps the environment's parts from frame to frame (IblCache).
    explicit RasterLights(const Scene& scene, int threads = 0, IblCache* ibl = nullptr);

    LightSet set;
    ImageBasedLighting environment;  // the map, when the scene has one
    /// Per source of the set: its VPLs (none for the delta lights).
    std::vector<std::vector<AreaPoint>> vpls;
    std::vector<float> min_dist2;  // per source: its area per VPL, m^2
    bool any_vpl = false;
};

/// Outgoing radiance toward wo at p: emission (front side), the ambient term, direct light
/// from every light, and what comes from far away: for mirrors and glass the uniform
/// environment `background`, or with a map its image-based lighting (lights.environment).
/// Each light's term is multiplied by its visibility at `sample`.
Color shade_point(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                  const RasterLights& lights, Color ambient, Color background,
                  const LightVisibility& vis = {}, size_t sample = 0);

/// What shade_point adds to the lights: emission, the ambient term, and what mirrors and glass
/// show of the background.
Color unlit_point(const Bsdf& bsdf, const ShadingFrame& frame, vec3 wo, Color ambient,
                  Color background, const ImageBasedLighting& environment);

/// shade_point with each light apart: returns unlit_point, and each source's term, unmasked,
/// into per_light[index] for every index of lights.set.sources() (flat and Gouraud shading
/// under a shadow technique, which mask each light's term per sample). Each term is computed
/// once, as shade_point computes it.
Color shade_point_per_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                            const RasterLights& lights, Color ambient, Color background,
                            Color* per_light);

}  // namespace svetlo
