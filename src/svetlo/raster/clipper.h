// Clipping in homogeneous coordinates (Sutherland and Hodgman, "Reentrant Polygon Clipping",
// CACM 1974; Blinn and Newell, "Clipping Using Homogeneous Coordinates", SIGGRAPH 1978).
// A triangle is clipped against the near and far planes (-w <= z <= w), which is what makes
// triangles crossing the camera plane draw correctly, and against a guard band around the
// viewport (|x|, |y| <= g w), which only keeps the rasterizer's fixed-point coordinates in
// range: triangles that merely leave the screen are not cut, the rasterizer's bounding box
// does that for free. Clipping in clip space, before the division by w, interpolates every
// attribute linearly, which is exact there.
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "svetlo/core/math.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// A vertex in clip space with the attributes the pipeline carries.
struct ClipVertex {
    vec4 clip{0.0f};
    vec3 world{0.0f};
    vec3 normal{0.0f};
    vec2 uv{0.0f};
    vec2 uv1{0.0f};           // the second set (TriangleList::uvs1; uv where it has none)
    vec4 vertex_color{1.0f};  // TriangleList::colors
    vec4 tangent{0.0f};       // TriangleList::tangents
    Color color{0.0f};        // Gouraud: the lit vertex colour
    float invw = 0.0f;        // 1 / clip.w (set for the vertex stage's and the clipper's outputs)
    float wh = 1.0f;          // the world point's homogeneous weight (0: a point at infinity)

    Varyings varyings() const { return {uv, uv1, vertex_color}; }
};

/// The varyings at the point of barycentric weights b[0..2] (perspective-correct ones for a
/// sample) of the triangle A, B, C.
inline Varyings varyings_at(const ClipVertex& A, const ClipVertex& B, const ClipVertex& C,
                            const float b[3]) {
    return {b[0] * A.uv + b[1] * B.uv + b[2] * C.uv, b[0] * A.uv1 + b[1] * B.uv1 + b[2] * C.uv1,
            b[0] * A.vertex_color + b[1] * B.vertex_color + b[2] * C.vertex_color};
}

/// A convex polygon of at most 3 + 6 vertices (each plane adds at most one).
struct ClipPolygon {
    std::array<ClipVertex, 9> v;
    int count = 0;
};

/// Clips triangle (a, b, c) to -w <= z <= w and |x|, |y| <= guard_x w, guard_y w; w > 0 is
/// implied by the near plane. Returns the polygon (count 0 when nothing is left), with
/// invw set on every vertex.
ClipPolygon clip_triangle(const ClipVertex& a, const ClipVertex& b, const ClipVertex& c,
                          float guard_x, float guard_y);

/// Whether a clip-space vertex can be projected: x, y and z finite, and w > 0 with 1/w finite
/// and non-zero (w neither infinite nor denormal). Coordinates that overflowed (world
/// coordinates near a float's limit) cannot be.
inline bool projectable(const vec4& p) {
    return p.w >= std::numeric_limits<float>::min() && p.w <= std::numeric_limits<float>::max() &&
           std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

/// True when a vertex can be projected and lies inside every clip plane; a triangle of three
/// such vertices needs no clipping (the common case). Then |x / w|, |y / w| are within the
/// guard band and |z / w| <= 1 (where g w overflows, w > FLT_MAX / g, so |x / w| < g still).
inline bool inside(const vec4& p, float gx, float gy) {
    return projectable(p) && p.z >= -p.w && p.z <= p.w && std::abs(p.x) <= gx * p.w &&
           std::abs(p.y) <= gy * p.w;
}

}  // namespace svetlo
