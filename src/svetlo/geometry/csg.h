// Constructive solid geometry by ray classification (Roth, "Ray Casting for Modeling Solids",
// CGIP 18(2), 1982). Each leaf gives the spans of the ray inside it: one for a convex
// analytic shape (shape_interval), as many as entry/exit pairs for a closed mesh; the tree
// combines the span lists with the boolean of each node, and the first span boundary past the
// origin is the hit. Boundaries keep the leaf and face they came from, and a flip flag for
// surfaces of subtracted children, whose outward normal is the reverse of their own.
//
// Coincident surfaces are resolved by one fixed rule: spans are closed intervals, events at
// equal t are processed entries first, and a result span or gap no longer than a few ULPs of
// the point's coordinates is a sliver between two surfaces that coincide up to rounding: the
// span is dropped, the gap closed. So touching solids merge in a union, and a difference
// whose cutter shares a face with the body (a cylinder as long as the box is thick) removes
// that face's skin entirely instead of leaving speckles.
#pragma once

#include <memory>
#include <vector>

#include "svetlo/geometry/bvh.h"
#include "svetlo/geometry/geometry.h"

namespace svetlo {

class CsgShape {
public:
    /// The tree of `csg` under `transform`; leaves without a material take `material`.
    CsgShape(const Csg& csg, const Transform& transform, uint32_t material);
    CsgShape(const CsgShape&) = delete;
    CsgShape& operator=(const CsgShape&) = delete;

    Bounds3 bounds() const { return nodes_.empty() ? Bounds3{} : nodes_[0].bounds; }
    /// Closest boundary of the solid with 0 < t < tmax; hit.sub holds the leaf (bit 31: the
    /// normal is flipped), hit.part the face or the mesh triangle.
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const;
    ShapeSurface surface(const Ray& ray, const ShapeHit& hit) const;
    /// True when the point lies inside the solid.
    bool contains(vec3 p) const;

    struct Boundary {
        float t;
        uint32_t leaf;  // kNoLeaf for the open end of a span that starts behind the ray
        int part;
        float u, v;
        bool flip;
    };
    struct Span {
        Boundary in, out;
    };
    static constexpr uint32_t kNoLeaf = ~0u;
    /// When two boundaries along a ray are one surface (csg.cpp); made once per ray.
    struct Coincidence;

private:
    struct Leaf {
        AnalyticShape shape;             // sphere, box, cylinder, cone (world space)
        std::unique_ptr<Geometry> mesh;  // or a closed mesh (world space) with its BVH
        std::unique_ptr<Bvh> bvh;
    };
    struct Node {
        CsgOp op = CsgOp::Union;
        int leaf = -1;                   // >= 0 for a leaf node
        std::vector<uint32_t> children;  // node indices
        Bounds3 bounds;
    };
    template <class List>
    void spans(uint32_t node, const Ray& ray, vec3 inv_d, const Coincidence& tolerance, float tmax,
               List& out) const;
    template <class List>
    void leaf_spans(uint32_t leaf, const Ray& ray, float tmax, List& out) const;
    uint32_t add(const Object& obj, const mat4& to_world, uint32_t material);

    std::vector<Leaf> leaves_;
    std::vector<Node> nodes_;  // nodes_[0] is the root
};

}  // namespace svetlo
