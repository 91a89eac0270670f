// Lights with area, sampled for direct lighting: the contract's `area` lights (which are
// also visible quads) and every object with an `emissive` material. Each emitter is a set of
// primitives, chosen in proportion to area, then sampled uniformly by area on the chosen one.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/geometry/geometry.h"

namespace svetlo {

struct Emitter {
    std::vector<uint32_t> prims;  // primitive ids
    std::vector<float> cdf;       // cumulative area over prims, normalised to end at 1
    float area = 0.0f;            // total, m^2
    int light_index = -1;         // index into Scene::lights for `area` lights, else -1
};

struct EmitterSample {
    vec3 p{0.0f};   // point on the emitter
    vec3 n{0.0f};   // its front-facing (emitting) unit normal
    vec2 uv{0.0f};
    uint32_t prim = 0;
    float pdf_area = 0.0f;  // 1 / m^2
};

/// Samples a point uniformly by area; u in [0,1)^2 and u_pick in [0,1).
EmitterSample sample_emitter(const Emitter& emitter, const Geometry& geometry, vec2 u, float u_pick);

/// Area of one primitive in world space.
float primitive_area(const Geometry& geometry, uint32_t id);

}  // namespace svetlo
