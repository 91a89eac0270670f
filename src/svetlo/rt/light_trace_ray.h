// The record of a ray sent from a surface toward a light, as svetlo trace writes it
// (docs/trace.md): Whitted's shadow rays and the path tracer's light samples alike.
#pragma once

#include "svetlo/geometry/ray.h"
#include "svetlo/scene/pixel_trace.h"

namespace svetlo {

/// A ray of `kind` from p (off the surface of geometric normal ng) along wi to `distance`,
/// child of ray `parent` at `depth`; noted visible or blocked by `visible`.
inline TraceRay light_trace_ray(const char* kind, int parent, int depth, vec3 p, vec3 ng, vec3 wi,
                                float distance, float visible) {
    TraceRay r;
    r.kind = kind;
    r.parent = parent;
    r.depth = depth;
    r.origin = offset_ray_origin(p, ng, wi);
    r.direction = wi;
    r.t = distance;
    r.note = visible > 0.0f ? "the light is visible" : "blocked";
    return r;
}

}  // namespace svetlo
