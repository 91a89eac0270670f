// Shadow rays, shared by the engines that trace them (Whitted, the path tracer): the test
// toward one light sample, the stratified sampling of the light set, and the visibility AOV
// of light 0 (docs/shading.md, "Radiometric conventions").
#pragma once

#include <cstdint>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/rt/rt_scene.h"

namespace svetlo {

/// True when the segment from p (offset off the surface along ng) to the light sample is
/// blocked. A point on a light with area is itself offset off its surface; a directional
/// light lies at infinity. Adds the ray to `rays`.
bool shadow_blocked(const RtScene& rt, vec3 p, vec3 ng, const LightSample& s, uint64_t& rays);

/// The fraction of light 0 that reaches p (normal ng, turned toward the viewer): 0 or 1 for a
/// delta light, the unoccluded fraction of max(samples, 16) stratified points for a light with
/// area; 1 where p faces away from the light, or there is no light 0.
float light0_visibility(const RtScene& rt, vec3 p, vec3 ng, int samples, Rng& rng, uint64_t& rays);

/// The light sampling of direct_light() (shading/direct_light.h) for the Whitted engine: one
/// sample per delta light, `n` stratified samples per light with area.
struct StratifiedLightSampling {
    const LightSet& lights;
    Rng& rng;
    int n;
    int count(size_t, const LightSet::Source& s) const { return s.delta ? 1 : n; }
    LightSample sample(size_t, const LightSet::Source& s, int k, vec3 p) {
        if (s.delta) return lights.sample(s, p, vec2(0.0f), 0.0f);
        vec2 u = stratified_sample(k, n, rng.next_2d());
        return lights.sample(s, p, u, rng.next_float());
    }
};

}  // namespace svetlo
