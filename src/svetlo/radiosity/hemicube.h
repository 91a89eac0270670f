// The hemicube (Cohen and Greenberg 1985): the form factors from a point to everything it
// sees, as five item-buffer renders through the rasterizer's pass entry point (draw_pass.h).
// A cube of half-side 1 sits on the point, its top face along the normal and four half faces
// around; each cell (u, v) at direction d (|d|^2 = u^2 + v^2 + 1) from the point carries the
// delta form factor dF = (d . n) dA / (pi |d|^4), so 1 / (pi r^4) dA on the top face and
// z dA / (pi r^4) on a side face, z the cell's height above the base. The element nearest
// along each cell's direction receives the cell's dF. Aliasing makes the error grow as
// elements shrink below a few cells (docs/radiosity.md measures it).
#pragma once

#include <vector>

#include "svetlo/geometry/triangle_list.h"
#include "svetlo/raster/draw_pass.h"

namespace svetlo {

class Hemicube {
public:
    /// `resolution` cells on a side of the top face; `bounds` enclose what is drawn.
    Hemicube(int resolution, const Bounds3& bounds);

    /// Adds to row[k] the form factor from the point x (unit normal n) to triangle k of
    /// `triangles` (row has one entry per triangle); returns the sum of the delta form factors
    /// that met a triangle. Faces are drawn on `threads` threads; the row does not depend on
    /// them.
    float gather(const TriangleList& triangles, vec3 x, vec3 n, std::vector<float>& row,
                 int threads);

    int resolution() const { return resolution_; }

private:
    int resolution_;
    Bounds3 bounds_;
    float nearest_;
    std::vector<float> top_, side_;  // delta form factors per cell, rows from the top
    RenderTargets targets_;
    PassMemory memory_;
};

}  // namespace svetlo
