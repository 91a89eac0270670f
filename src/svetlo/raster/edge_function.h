// Triangle setup for rasterization with edge functions (Pineda, "A Parallel Algorithm for
// Polygon Rasterization", SIGGRAPH 1988) in fixed point, with the top-left fill rule of
// Direct3D and OpenGL: a sample exactly on an edge shared by two triangles belongs to
// exactly one of them, so meshes have neither cracks nor doubly drawn pixels.
//
// Screen coordinates are pixels, x right and y down, snapped to 1/256 of a pixel
// (kSubpixel). For a triangle wound so that its area is positive, the edge function of the
// edge a -> b at a point p is E(p) = (b.x - a.x)(p.y - a.y) - (b.y - a.y)(p.x - a.x): it
// grows toward the inside and is zero on the edge. Divided by twice the area, the three
// edge functions are the barycentric coordinates of p in screen space.
#pragma once

#include <cstdint>

#include "svetlo/core/math.h"

namespace svetlo {

inline constexpr int kSubpixelBits = 8;
inline constexpr int32_t kSubpixel = 1 << kSubpixelBits;

/// Pixel coordinate to fixed point, rounded to the nearest step (half away from zero; inline,
/// where std::lround is a library call).
inline int32_t to_fixed(float x) {
    float v = x * static_cast<float>(kSubpixel);
    return static_cast<int32_t>(v >= 0.0f ? v + 0.5f : v - 0.5f);
}

/// The fill rule for the edge E(x, y) = a x + b y + c: the inside lies where E grows. A left
/// edge has the inside to its right (a > 0); a top edge is horizontal with the inside below it
/// (a == 0, b > 0; y points down). Samples on such an edge are inside.
inline bool top_left(int64_t a, int64_t b) { return a > 0 || (a == 0 && b > 0); }

struct Edge {
    int64_t a = 0, b = 0;  // E(x, y) = a x + b y + c, in fixed-point units
    int64_t c = 0;
    int64_t bias = 0;  // 0 on a top or left edge, -1 otherwise: E + bias >= 0 is inside

    /// The edge from (x0, y0) to (x1, y1) of a triangle with positive area.
    static Edge make(int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
        Edge e;
        e.a = -(y1 - y0);
        e.b = x1 - x0;
        e.c = -(e.a * x0 + e.b * y0);
        e.bias = top_left(e.a, e.b) ? 0 : -1;
        return e;
    }
    int64_t at(int64_t x, int64_t y) const { return a * x + b * y + c; }
};

/// Twice the signed area of the fixed-point triangle in pixel coordinates (x right, y down):
/// positive when the vertices turn clockwise as the viewer sees the screen.
inline int64_t signed_area2(const int32_t x[3], const int32_t y[3]) {
    return (static_cast<int64_t>(x[1]) - x[0]) * (static_cast<int64_t>(y[2]) - y[0]) -
           (static_cast<int64_t>(x[2]) - x[0]) * (static_cast<int64_t>(y[1]) - y[0]);
}

/// Whether the camera sees a triangle's front (counter-clockwise) side, from signed_area2:
/// rows grow downward, so a front face, counter-clockwise as seen, has a negative area. For a
/// planar triangle this is the sign of ng . wo at every point of it (shading_frame.h), the
/// rule the stencil's per-face operations and back-face culling follow.
inline bool front_facing(int64_t area2) { return area2 < 0; }

}  // namespace svetlo
