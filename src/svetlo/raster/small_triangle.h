// A small triangle (at most kSmall pixels on each side) at one sample per pixel, in the form
// its rasterization reads: the three edge functions and the depth plane at the sample of one
// corner pixel of its bounds, and their steps per pixel. Relative to that sample every edge
// value a triangle's bounds can meet fits in 32 bits, so four pixels are tested at once in
// 32-bit lanes (rasterize.cpp). The frame's colour pass makes it from a SetupTriangle; a
// depth-only pass keeps it as its record (DepthTriangle), made once at setup.
#pragma once

#include <cstdint>

#include "svetlo/raster/edge_function.h"

namespace svetlo::raster {

constexpr int kSmall = 32;  // pixels: the largest side of a "small" triangle

/// Edge k (the weight of vertex k) of a triangle wound so that its area is positive, running
/// from vertex i = k + 1 to j = k + 2 (Edge::make), at the corner sample and per pixel.
struct SmallEdges {
    int32_t w[3];       // E_k + bias_k at the corner sample: covered where all three are >= 0
    int32_t bias[3];    // the top-left rule's: 0 on a top or left edge, else -1
    int32_t step_x[3];  // E_k's change one pixel to the right, (y_i - y_j) 256
    int32_t step_y[3];  // and one pixel down, (x_j - x_i) 256
};

/// From the vertices relative to the corner sample (fixed point). |dx|, |dy| <= kSmall 256
/// and |rx|, |ry| <= (kSmall + 1) 256: every product below 2^27, and a bound's far corner
/// E + 32 (|step_x| + |step_y|) below 2^29.
inline SmallEdges small_edges(const int32_t rx[3], const int32_t ry[3]) {
    SmallEdges e;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const int32_t dx = rx[j] - rx[i], dy = ry[j] - ry[i];
        e.bias[k] = top_left(-dy, dx) ? 0 : -1;
        // E(p) = dx (p.y - y_i) - dy (p.x - x_i) at p = the corner sample, (0, 0) here.
        e.w[k] = dy * rx[i] - dx * ry[i] + e.bias[k];
        e.step_x[k] = -dy * kSubpixel;
        e.step_y[k] = dx * kSubpixel;
    }
    return e;
}

/// The depth key's plane over the pixels: z = z0 + dzdx i + dzdy j at the corner sample's
/// pixel moved i right and j down (evaluated so in float by the rasterizer, the same way on
/// every path).
struct DepthPlane {
    float z0, dzdx, dzdy;
};

/// From the same relative vertices, their depth keys, and 1 / twice the fixed-point area
/// (SetupTriangle::inv_area); in double, rounded once.
inline DepthPlane depth_plane(const int32_t rx[3], const int32_t ry[3], const float z[3],
                              float inv_area) {
    const double per_pixel = static_cast<double>(kSubpixel) * static_cast<double>(inv_area);
    const double z1 = z[1] - z[0], z2 = z[2] - z[0];
    // The weights' gradients are edges 1 and 2's coefficients (a, b) over twice the area.
    const double dzdx =
        (static_cast<double>(ry[2] - ry[0]) * z1 + static_cast<double>(ry[0] - ry[1]) * z2) *
        per_pixel;
    const double dzdy =
        (static_cast<double>(rx[0] - rx[2]) * z1 + static_cast<double>(rx[1] - rx[0]) * z2) *
        per_pixel;
    const double z0 = static_cast<double>(z[0]) -
                      (dzdx * static_cast<double>(rx[0]) + dzdy * static_cast<double>(ry[0])) /
                          static_cast<double>(kSubpixel);
    return {static_cast<float>(z0), static_cast<float>(dzdx), static_cast<float>(dzdy)};
}

/// A small triangle of a depth-only pass (a shadow map's depth pass: one sample per pixel,
/// depth tested and written, nothing else kept): what its rasterization needs and nothing
/// more, half a cache line, where a SetupTriangle takes a whole one.
struct DepthTriangle {
    // Pixels [bx0, bx1] x [by0, by1] that may hold a covered sample (SetupTriangle's bounds).
    uint16_t bx0, by0, bx1, by1;
    // The vertices, wound so that the area is positive, in fixed point relative to the
    // sample of pixel (bx0, by0): within (kSmall + 1) 256 of it.
    int16_t rx[3], ry[3];
    DepthPlane plane;  // corner: pixel (bx0, by0)

    SmallEdges edges() const {
        const int32_t x[3] = {rx[0], rx[1], rx[2]}, y[3] = {ry[0], ry[1], ry[2]};
        return small_edges(x, y);
    }
};
static_assert(sizeof(DepthTriangle) == 32);

}  // namespace svetlo::raster
