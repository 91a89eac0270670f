// The lighting core shared by every engine: what a surface gives before any light is summed,
// and the direct-light sum
//
//   L_direct(p, wo) = sum over lights of  f(wo, wi) E(wi) cos(theta) V
//
// (docs/shading.md, "Radiometric conventions"). E is a light sample's irradiance
// (light_set.h), f the BSDF (bsdf.h), theta the angle between wi and the shading normal, and
// V the visibility from a callable the engine passes: traced shadow rays (Whitted, the path
// tracer), a per-light shadow mask (the rasterizer's shadow techniques), or 1 (no shadows).
// A light with area contributes the mean over its samples. The path tracer estimates the same
// sum with one light per vertex, chosen by power (pt/light_selection.h), through
// unoccluded_light.
#pragma once

#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/light_set.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

/// L_e (from the front side only) + k_a I_a, the empirical ambient term, darkened by the
/// material's occlusion texture.
inline Color emitted_and_ambient(const Bsdf& bsdf, const ShadingFrame& frame, Color ambient) {
    Color L(0.0f);
    if (frame.front) L += bsdf.emission;  // black unless the material emits
    return L + bsdf.ambient * ambient * bsdf.occlusion;
}

/// f(wo, wi) E cos(theta) for one light sample, before occlusion: zero when wi lies below the
/// shading or the geometric normal, or the sample brings no light.
inline Color unoccluded_light(const Bsdf& bsdf, const ShadingFrame& frame, vec3 wo,
                              const LightSample& s) {
    float cos_theta = glm::dot(frame.ns, s.wi);
    if (cos_theta <= 0.0f || glm::dot(frame.ng, s.wi) <= 0.0f || is_black(s.irradiance))
        return Color(0.0f);
    return eval_bsdf(bsdf, frame.ns, wo, s.wi) * s.irradiance * cos_theta;
}

/// The direct light at p from one source, the one at `index` in lights.sources(): the mean of
/// f E cos(theta) V over its samples. `sampling` says how a source is sampled: `int
/// count(index, source)` samples, and `LightSample sample(index, source, k, p)` for the k-th.
/// `visible(index, sample)` returns V in [0, 1]; it is asked only for samples that bring light.
/// The caller has checked that the BSDF has lobes.
template <class Sampling, class Visibility>
Color source_light(const LightSet::Source& source, size_t index, const Bsdf& bsdf, vec3 p,
                   const ShadingFrame& frame, vec3 wo, Sampling& sampling, Visibility& visible) {
    const int n = sampling.count(index, source);
    Color sum(0.0f);
    for (int k = 0; k < n; ++k) {
        LightSample s = sampling.sample(index, source, k, p);
        Color c = unoccluded_light(bsdf, frame, wo, s);
        if (is_black(c)) continue;
        float v = visible(index, s);
        if (v > 0.0f) sum += v == 1.0f ? c : c * v;
    }
    return n == 1 ? sum : sum / static_cast<float>(n);
}

/// The direct light at p: source_light summed over every source.
template <class Sampling, class Visibility>
Color direct_light(const LightSet& lights, const Bsdf& bsdf, vec3 p, const ShadingFrame& frame,
                   vec3 wo, Sampling&& sampling, Visibility&& visible) {
    Color L(0.0f);
    if (!bsdf.has_lobes()) return L;
    const auto& sources = lights.sources();
    for (size_t index = 0; index < sources.size(); ++index)
        L += source_light(sources[index], index, bsdf, p, frame, wo, sampling, visible);
    return L;
}

}  // namespace svetlo
