// Implicit (F-rep) surfaces: a tree of signed-distance primitives and operations evaluated at
// a point, rendered by sphere tracing (Hart, "Sphere Tracing: A Geometric Method for the
// Antialiased Ray Tracing of Implicit Surfaces", The Visual Computer 12(10), 1996).
//
// Every node is kept 1-Lipschitz, so |f(p)| never exceeds the distance from p to the surface
// and a ray may always advance by |f|: primitives are exact distances (Quilez's formulas), min
// and max keep the bound, the polynomial smooth minimum does too (its weights sum to one), and
// a node under an affine map M divides by the largest singular value of M^-1.
#pragma once

#include <vector>

#include "svetlo/geometry/shapes.h"

namespace svetlo {

class SdfShape {
public:
    /// The tree `root` placed in the world by `to_world`.
    SdfShape(const SdfNode& root, const mat4& to_world);

    /// Signed distance bound at a world-space point: negative inside.
    float eval(vec3 p) const { return eval_node(0, p); }
    /// Unit outward normal: the normalised gradient by central differences.
    vec3 normal(vec3 p) const;
    /// Conservative world-space bounds of the solid; infinite when it is unbounded (a plane).
    Bounds3 bounds() const { return bounds_; }

    /// First surface crossing with 0 < t < tmax, found by sphere tracing and refined by
    /// bisection to float precision. The point returned lies on the side the ray came from.
    bool intersect(const Ray& ray, float tmax, float& t) const;
    ShapeSurface surface(const Ray& ray, float t) const;

private:
    struct Node {
        SdfOp op;
        vec3 a, b;
        float r1, r2, smooth;
        bool transformed;
        mat4 to_local;          // the parent's space to this node's
        mat4 to_parent;         // and back
        float inv_lipschitz;    // 1 / ||linear part of to_local||_2: keeps the bound
        uint32_t first, count;  // children: a range of child_index_
    };
    uint32_t flatten(const SdfNode& n, const mat4& to_parent);
    float eval_node(uint32_t k, vec3 p) const;
    Bounds3 node_bounds(uint32_t k) const;  // in the parent's space

    std::vector<Node> nodes_;  // nodes_[0] is the root, its parent space the world
    std::vector<uint32_t> child_index_;
    Bounds3 bounds_;
    float scale_ = 1.0f;  // sets the tolerances: the bounds' diagonal, or 1 when unbounded
};

}  // namespace svetlo
