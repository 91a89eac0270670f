// Line rasterization for the wireframe overlay. Pixel (i, j) has its centre at
// (i + 1/2, j + 1/2); endpoints are in pixels.
//
// - Bresenham ("Algorithm for computer control of a digital plotter", IBM Systems Journal
//   1965): the pixels nearest to the line, one per step along the major axis, chosen with an
//   integer error term; aliased (coverage 1).
// - Wu ("An Efficient Antialiasing Technique", SIGGRAPH 1991): at each step along the major
//   axis the two pixels straddling the line share the intensity by their distance to it,
//   with fractional coverage at the endpoints.
#pragma once

#include "svetlo/core/math.h"

namespace svetlo {

/// Calls plot(i, j, coverage, t) for each pixel of the line from p0 to p1; t in [0, 1] is
/// the parameter along the line (for interpolating depth).
template <class Plot>
void draw_line_bresenham(vec2 p0, vec2 p1, Plot&& plot) {
    int x0 = static_cast<int>(std::floor(p0.x)), y0 = static_cast<int>(std::floor(p0.y));
    int x1 = static_cast<int>(std::floor(p1.x)), y1 = static_cast<int>(std::floor(p1.y));
    int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    int steps = std::max(dx, -dy), step = 0;
    for (;;) {
        plot(x0, y0, 1.0f,
             steps == 0 ? 0.0f : static_cast<float>(step) / static_cast<float>(steps));
        if (x0 == x1 && y0 == y1) break;
        int e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            x0 += sx;
        }
        if (e2 <= dx) {
            err += dx;
            y0 += sy;
        }
        ++step;
    }
}

template <class Plot>
void draw_line_wu(vec2 p0, vec2 p1, Plot&& plot) {
    // Work with pixel centres at integers.
    float x0 = p0.x - 0.5f, y0 = p0.y - 0.5f, x1 = p1.x - 0.5f, y1 = p1.y - 0.5f;
    bool steep = std::abs(y1 - y0) > std::abs(x1 - x0);
    if (steep) {
        std::swap(x0, y0);
        std::swap(x1, y1);
    }
    bool reversed = x0 > x1;
    if (reversed) {
        std::swap(x0, x1);
        std::swap(y0, y1);
    }
    float dx = x1 - x0, dy = y1 - y0;
    float gradient = dx == 0.0f ? 1.0f : dy / dx;
    auto put = [&](int major, int minor, float c, float x) {
        float t = dx == 0.0f ? 0.0f : std::clamp((x - x0) / dx, 0.0f, 1.0f);
        if (reversed) t = 1.0f - t;
        if (c <= 0.0f) return;
        if (steep)
            plot(minor, major, c, t);
        else
            plot(major, minor, c, t);
    };
    auto fpart = [](float v) { return v - std::floor(v); };
    // First endpoint.
    float xend = std::round(x0), yend = y0 + gradient * (xend - x0);
    float xgap = 1.0f - fpart(x0 + 0.5f);
    int xa = static_cast<int>(xend), ya = static_cast<int>(std::floor(yend));
    put(xa, ya, (1.0f - fpart(yend)) * xgap, xend);
    put(xa, ya + 1, fpart(yend) * xgap, xend);
    float inter = yend + gradient;
    // Second endpoint.
    xend = std::round(x1);
    yend = y1 + gradient * (xend - x1);
    xgap = fpart(x1 + 0.5f);
    int xb = static_cast<int>(xend), yb = static_cast<int>(std::floor(yend));
    // The span between them.
    for (int x = xa + 1; x < xb; ++x) {
        int y = static_cast<int>(std::floor(inter));
        put(x, y, 1.0f - fpart(inter), static_cast<float>(x));
        put(x, y + 1, fpart(inter), static_cast<float>(x));
        inter += gradient;
    }
    if (xb != xa) {
        put(xb, yb, (1.0f - fpart(yend)) * xgap, xend);
        put(xb, yb + 1, fpart(yend) * xgap, xend);
    }
}

}  // namespace svetlo
