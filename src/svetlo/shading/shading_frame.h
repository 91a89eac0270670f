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

/// ng: unit geometric normal of the front side; ns: the shading normal, unit or zero (none);
/// wo: unit direction from the surface to the viewer (world space).
inline ShadingFrame make_shading_frame(vec3 ng, vec3 ns, vec3 wo) {
    ShadingFrame f;
    f.front = glm::dot(ng, wo) > 0.0f;
    f.ng = f.front ? ng : -ng;
    f.ns = ns;
    if (glm::dot(ns, ns) == 0.0f) f.ns = f.ng;      // no shading normal
    if (glm::dot(f.ns, f.ng) < 0.0f) f.ns = -f.ns;  // onto the seen side
    if (glm::dot(f.ns, wo) <= 0.0f) f.ns = f.ng;    // interpolated past the silhouette
    return f;
}

}  // namespace svetlo
