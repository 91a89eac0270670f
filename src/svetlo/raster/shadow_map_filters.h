// A shadow map's depths and the filters that read them (shadow_maps.cpp makes the maps).
//
//   none  one texel compared with the receiver's distance, less the bias
//   pcf   kernel x kernel bilinear comparisons (Reeves, Salesin and Cook 1987), as OpenGL's
//         sampler2DShadow with GL_LINEAR does per tap
//   pcss  percentage-closer soft shadows (Fernando 2005): a blocker search, a penumbra from
//         the light's width, the blockers' mean distance and the receiver's, filtered that wide
#pragma once

#include <algorithm>
#include <vector>

#include "svetlo/raster/camera_matrices.h"
#include "svetlo/scene/scene.h"

namespace svetlo::raster {

/// One depth map: the caster's camera and what it saw.
struct DepthMap {
    CameraMatrices cam;
    mat4 view_projection{1.0f};
    int res = 0;
    std::vector<float> distance;  // res x res, rows from the top (m; +infinity: nothing)
    float texel = 0.0f;           // perspective: texel width per metre of distance (2 t / res);
                                  // orthographic: texel width in metres

    float at(int x, int y) const {
        x = std::clamp(x, 0, res - 1);
        y = std::clamp(y, 0, res - 1);
        return distance[static_cast<size_t>(y) * static_cast<size_t>(res) + static_cast<size_t>(x)];
    }
    /// The receiver's distance in the map's terms: radial, or along the axis.
    float receiver(vec3 q) const {
        return cam.orthographic ? glm::dot(q - cam.eye, cam.forward) : glm::length(q - cam.eye);
    }
    /// A texel's width in metres at the receiver's distance d.
    float texel_at(float d) const { return cam.orthographic ? texel : texel * d; }
};

/// How many texels of filter the maps must hold beyond the cube faces' 90 degrees.
int margin_texels(const ShadowMapSettings& sm, int res);

/// 1 where the stored distance is not nearer than the receiver's, less the bias.
inline float shadow_compare(float stored, float receiver, float bias) {
    return stored >= receiver - bias ? 1.0f : 0.0f;
}

/// PCF's kernel when its taps lie one texel apart (docs/kernels.md): the (n + 1) x (n + 1)
/// texels from `d` (rows `res` floats apart), each 1 where lit (stored >= limit), weighted 1
/// inside and by the bilinear fractions (1 - fx, fx across, 1 - fy, fy down) on the border.
/// The twin states it; the SSE form (n <= 3: a row in one load) adds the same terms in another
/// order (tests/raster/kernel_twins_test.cpp: within 1e-5).
namespace twin {
float pcf_block(const float* d, int res, int n, float fx, float fy, float limit);
}  // namespace twin
#if SVETLO_SIMD
namespace sse {
float pcf_block(const float* d, int res, int n, float fx, float fy, float limit);
}  // namespace sse
#endif

/// settings.kernel x kernel bilinear taps spread over [-radius, radius] texels around pixel
/// position px of map m, for a receiver at distance `receiver` (m) and a slope-scaled bias
/// of `slope` metres per texel.
float shadow_pcf(const DepthMap& m, const ShadowMapSettings& settings, vec2 px, float receiver,
                 float radius, float slope);

/// Percentage-closer soft shadows under a caster of width `size` (m).
float shadow_pcss(const DepthMap& m, const ShadowMapSettings& settings, float size, vec2 px,
                  float receiver, float slope);

}  // namespace svetlo::raster
