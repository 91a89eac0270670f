// Drawing the radiosity solution from the camera (docs/radiosity.md). The irradiance of the
// leaves becomes a continuous field over every surface: each leaf corner takes the area
// mean of the leaves that share it (on the same side of a smooth surface: normals within
// 37 degrees), and a corner that lies inside a coarser leaf's edge (a T-vertex, where
// subdivision levels meet) takes the value that edge interpolates, so the shading has no
// cracks. A pixel interpolates its leaf's three corners (Gouraud's rule) and multiplies by
// its own diffuse reflectance: L = L_e + rho / pi E.
#pragma once

#include <vector>

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

}  // namespace svetlo
