// Which side of a surface the viewer sees, decided once for every engine and every path
// (Whitted, the rasterizer's scalar and SIMD shading, and the engines to come).
//
// The front side is the one the geometric normal ng points to: a triangle's counter-clockwise
// side, a quad's edge_u x edge_v, a closed shape's outside. Emission leaves the front side only;
// every other surface is two-sided (docs/shading.md): seen from behind, it is shaded with
// both normals turned toward the viewer. The SIMD kernel (raster/simd_kernel.inc) applies the
// same three rules lane by lane.
#pragma once

#include "svetlo/core/math.h"

namespace svetlo {

struct ShadingFrame {
    vec3 ng{0.0f};       // unit geometric normal, turned toward the viewer
    vec3 ns{0.0f};       // unit shading normal on ng's side and facing the viewer (else ng)
    bool front = false;  // the viewer sees the front side
};

/// A shading normal n (unit, or zero: none) turned to the side the viewer sees, whose
/// geometric normal is ng_seen: onto that side, and ng_seen itself where n faces away from wo.
inline vec3 turned_normal(vec3 n, vec3 ng_seen, vec3 wo) {
    if (glm::dot(n, n) == 0.0f) return ng_seen;    // no shading normal
    if (glm::dot(n, ng_seen) < 0.0f) n = -n;       // onto the seen side
    return glm::dot(n, wo) <= 0.0f ? ng_seen : n;  // interpolated past the silhouette
}

/// ng: unit geometric normal of the front side; ns: the shading normal, unit or zero (none);
/// wo: unit direction from the surface to the viewer (world space).
inline ShadingFrame make_shading_frame(vec3 ng, vec3 ns, vec3 wo) {
    ShadingFrame f;
    f.front = glm::dot(ng, wo) > 0.0f;
    f.ng = f.front ? ng : -ng;
    f.ns = turned_normal(ns, f.ng, wo);
    return f;
}

/// A clear coat's own normal (coat_shading_normal: zero for none) turned as f's shading
/// normal is, for Bsdf::coat_normal (zero stays zero: the coat takes f.ns).
inline vec3 seen_coat_normal(vec3 coat_ns, const ShadingFrame& f, vec3 wo) {
    return glm::dot(coat_ns, coat_ns) == 0.0f ? vec3(0.0f) : turned_normal(coat_ns, f.ng, wo);
}

}  // namespace svetlo
