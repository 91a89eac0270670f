// Drawing the radiosity solution from the camera (docs/radiosity.md). The irradiance of the
// leaves becomes a continuous field over every surface: each leaf corner takes the area
// mean of the leaves that share it (on the same side of a smooth surface: normals within
// 37 degrees), and a corner that lies inside a coarser leaf's edge (a T-vertex, where
// subdivision levels meet) takes the value that edge interpolates, so the shading has no
// cracks. A pixel interpolates its leaf's three corners (Gouraud's rule) and multiplies by
// its own diffuse reflectance: L = L_e + rho / pi E.
#pragma once

#include <vector>

#include "svetlo/geometry/ray.h"
#include "svetlo/radiosity/element_tree.h"
#include "svetlo/radiosity/solver.h"

namespace svetlo {

class IrradianceField {
public:
    /// From the leaves' total and indirect irradiance (per node, both sides).
    IrradianceField(const ElementTree& tree, const std::vector<Sides>& total,
                    const std::vector<Sides>& indirect);

    struct Value {
        Color total{0.0f}, indirect{0.0f};
    };
    /// The field at barycentrics (b1, b2) of root triangle `root`, on `side`.
    Value at(uint32_t root, vec2 b, int side) const;

private:
    struct Corner {
        vec3 normal;
        Color value[4];  // total front, total back, indirect front, indirect back
        float weight = 0.0f;
    };
    const ElementTree& tree_;
    std::vector<Corner> corners_;
    std::vector<uint32_t> corner_of_;  // per node, 3 corner ids (leaves only)
};

/// Where a camera sample meets the triangle the item buffer gave it.
struct DisplaySample {
    vec3 x{0.0f};           // the point, world space
    vec3 n{0.0f};           // the unit normal of the side the camera sees
    vec2 b{0.0f};           // barycentrics (b1, b2) of the triangle
    Varyings at;            // interpolated texture coordinates and vertex colour
    float distance = 0.0f;  // from the camera, scene units
    int side = 0;           // 0: the camera sees the front (counter-clockwise) side
};

/// The sample's ray met on the plane of triangle t (unit front normal ng) of `list`, its
/// barycentrics clamped into the triangle: the item buffer says the sample covers t, and the
/// ray may miss it by a rounding.
DisplaySample sample_on_triangle(const TriangleList& list, uint32_t t, vec3 ng, const Ray& ray);

/// The patches AOV at barycentrics b of root t, on `side`: the leaf's own radiance
/// rho / pi E, darkened within `footprint` (scene units, about a pixel) of the leaf's edges,
/// and red near the edges of its patch (the level of `patch_size`).
Color patches_view(const ElementTree& tree, uint32_t t, vec2 b, int side,
                   const std::vector<Sides>& E, Color rho, float patch_size, float footprint);

}  // namespace svetlo
