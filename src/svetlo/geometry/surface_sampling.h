// Points sampled uniformly by area on the primitives of a Geometry: what lights with area
// (area lights, emissive objects) need for direct lighting (shading/light_set.h), and what
// radiosity's patches will need.
#pragma once

#include <cstdint>

#include "svetlo/geometry/geometry.h"

namespace svetlo {

struct SurfaceSample {
    vec3 p{0.0f};  // world-space point on the primitive
    vec3 n{0.0f};  // its unit front normal (a triangle's counter-clockwise side, a shape's outside)
    Varyings at;   // what its material's colours read there
};

/// Side `side` of the box from `lo` to `hi` in its own space: 0-5 are the low and the high
/// side of x, then of y, then of z, the order sample_primitive picks them in. Its points are
/// corner + u edge_u + v edge_v (u along the next axis, v the one after), n its unit outward
/// normal, area = |edge_u| |edge_v|.
struct BoxSide {
    vec3 corner, edge_u, edge_v, n;
    float area;
};
BoxSide box_side(vec3 lo, vec3 hi, int side);

/// A point of primitive `id`, uniformly distributed by area: u in [0,1)^2, and u_part in
/// [0,1) picks the face of a box, cylinder or cone in proportion to its area. Exact for
/// untransformed shapes and under uniform scaling.
SurfaceSample sample_primitive(const Geometry& geometry, uint32_t id, vec2 u, float u_part);

/// The same for triangle `id` whose unit front normal n is known (the light set keeps its
/// emitters' normals, saving the cross product's normalisation per sample).
SurfaceSample sample_triangle_primitive(const Geometry& geometry, uint32_t id, vec2 u, vec3 n);

/// Area of one primitive in world space (m^2).
float primitive_area(const Geometry& geometry, uint32_t id);

}  // namespace svetlo
