// Which light the path tracer samples at a vertex: one, chosen in proportion to an estimate of
// its power, mixed with a uniform choice so that no light is starved by a poor estimate (a
// textured emitter, a spot light aimed away). One shadow ray per vertex then serves any
// number of lights; the estimate divides by the choice's probability, and the MIS weights
// multiply the light's pdf by it (pbrt-v4's power light sampler, section 12.6).
#pragma once

#include <vector>

#include "svetlo/shading/light_set.h"

namespace svetlo {

/// An estimate of a source's luminous power (W, luminance-weighted): pi L A for a light with
/// area (its radiance at one point standing for all of it), 4 pi I for a point light, the
/// outer cone's solid angle times I for a spot light, and for a directional light its
/// irradiance on a disc of `radius`.
double light_power(const LightSet& lights, const LightSet::Source& source, const Scene& scene,
                   float radius);

class LightSelection {
public:
    /// `radius`: the scene's bounding radius, for the power of directional lights.
    LightSelection(const LightSet& lights, const Scene& scene, float radius);

    /// The source chosen by u in [0, 1), with its probability. Requires a non-empty set.
    size_t pick(float u, float& probability) const;
    /// The probability that pick() chooses source `index`.
    float probability(size_t index) const { return probability_[index]; }
    bool empty() const { return probability_.empty(); }

private:
    std::vector<float> probability_;
    std::vector<float> cdf_;  // ends at 1
};

}  // namespace svetlo
