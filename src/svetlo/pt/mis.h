// Multiple importance sampling weights (Veach and Guibas, "Optimally Combining Sampling
// Techniques for Monte Carlo Rendering", SIGGRAPH 1995) for the path tracer's two ways of
// finding a light with area: light sampling and BSDF sampling, under render.mis.
#pragma once

#include "svetlo/core/sampling.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// The weight of a sample of the light strategy (pdf `light`, the BSDF's `bsdf`) under `mode`.
inline float light_weight(MisMode mode, float light, float bsdf) {
    if (mode == MisMode::Power) return power_heuristic(light, bsdf);
    return mode == MisMode::LightOnly ? 1.0f : 0.0f;
}

/// The weight of a sample of the BSDF strategy.
inline float bsdf_weight(MisMode mode, float bsdf, float light) {
    if (mode == MisMode::Power) return power_heuristic(bsdf, light);
    return mode == MisMode::BsdfOnly ? 1.0f : 0.0f;
}

}  // namespace svetlo
