// A small triangle (at most kSmall pixels on each side) at one sample per pixel, in the form
// its rasterization reads: the three edge functions at the first sample of a span, the depth
// plane, and their steps per pixel. Relative to that sample every edge value a triangle's
// bounds can meet fits in 32 bits, so four pixels are tested at once in 32-bit lanes
// (rasterize.cpp). The frame's colour pass makes it from a SetupTriangle; a
// depth-only pass keeps its vertices relative to one corner and its plane as a record
// (DepthTriangle), made once at setup.
#pragma once

#include <cstdint>

#include "svetlo/raster/edge_function.h"

namespace svetlo::raster {

constexpr int kSmall = 32;  // pixels: the largest side of a "small" triangle

/// Edge k (the weight of vertex k) of a triangle wound so that its area is positive, running
/// from vertex i = k + 1 to j = k + 2 (Edge::make), at an origin sample (a corner of its
/// bounds, or where a span of them in a tile starts) and per pixel.
struct SmallEdges {
    int32_t w[3];       // E_k + bias_k at the origin: covered where all three are >= 0
    int32_t bias[3];    // the top-left rule's: 0 on a top or left edge, else -1
    int32_t step_x[3];  // E_k's change one pixel to the right, (y_i - y_j) 256
    int32_t step_y[3];  // and one pixel down, (x_j - x_i) 256
};

/// From the vertices relative to the origin sample (fixed point), a sample of the bounds.
/// |dx|, |dy| <= kSmall 256 and |rx|, |ry| <= (kSmall + 1) 256: every product below 2^27, and a
/// bound's far corner E + 32 (|step_x| + |step_y|) below 2^29.
inline SmallEdges small_edges(const int32_t rx[3], const int32_t ry[3]) {
    SmallEdges e;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const int32_t dx = rx[j] - rx[i], dy = ry[j] - ry[i];
        e.bias[k] = top_left(-dy, dx) ? 0 : -1;
        // E(p) = dx (p.y - y_i) - dy (p.x - x_i) at p = the origin, (0, 0) here.
        e.w[k] = dy * rx[i] - dx * ry[i] + e.bias[k];
        e.step_x[k] = -dy * kSubpixel;
        e.step_y[k] = dx * kSubpixel;
    }
    return e;
}

/// The depth key's plane: vertex 0's key and the steps per pixel right and down.
struct DepthPlane {
    float z0, dzdx, dzdy;
};

/// From the vertices relative to any sample (fixed point), their depth keys, and 1 / twice the
/// fixed-point area (SetupTriangle::inv_area): the gradients in double, rounded once.
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
    return {z[0], static_cast<float>(dzdx), static_cast<float>(dzdy)};
}

/// The depth key at the sample (dx, dy) from vertex 0 (fixed point), where a span of a row
/// starts; along it, dzdy per row and dzdx per pixel are added in float. The same operations
/// on every path, so every path stores the same depths.
inline float depth_at(const DepthPlane& p, int32_t dx, int32_t dy) {
    return p.z0 + p.dzdx * static_cast<float>(static_cast<double>(dx) / kSubpixel) +
           p.dzdy * static_cast<float>(static_cast<double>(dy) / kSubpixel);
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
    DepthPlane plane;
};
static_assert(sizeof(DepthTriangle) == 32);

}  // namespace svetlo::raster
