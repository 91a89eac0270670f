// Multiple importance sampling weights (Veach and Guibas, "Optimally Combining Sampling
// Techniques for Monte Carlo Rendering", SIGGRAPH 1995) for the path tracer's two ways of
// finding a light with area: light sampling and BSDF sampling, under render.mis.
#pragma once

#include "svetlo/scene/scene.h"

namespace svetlo {

/// The power heuristic (beta = 2) for a sample of the strategy with pdf `a` against the
/// other's `b`, pdfs already multiplied by their strategies' sample counts: a^2 / (a^2 + b^2),
/// computed from the ratio of the smaller to the larger, so that pdfs past 1e19 (a point at
/// the horizon of an infinite plane sampling a light edge-on) do not overflow to inf / inf.
inline float power_heuristic(float a, float b) {
    if (!(a > 0.0f)) return 0.0f;
    if (!(b > 0.0f)) return 1.0f;
    if (a == b) return 0.5f;  // infinite pdfs included
    if (a > b) {
        float r = b / a;
        return 1.0f / (1.0f + r * r);
    }
    float r = a / b;
    return r * r / (1.0f + r * r);
}

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
