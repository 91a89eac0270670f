// An octree: the scene's bounds split at their centre into eight children, recursively, while
// a node holds more than kMaxLeaf primitives (Glassner, "Space Subdivision for Fast Ray
// Tracing", IEEE CG&A 1984). A primitive is listed in every leaf its bounds overlap.
// Traversal visits the children a ray pierces nearest first and skips nodes that begin beyond
// the closest hit so far. It adapts to uneven scenes better than a grid; unlike a BVH it
// duplicates primitives that straddle splits and cannot fit its boxes to the geometry.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/geometry/accel.h"

namespace svetlo {

struct OctreeNode {
    uint32_t first;  // inner: index of the first of 8 consecutive children; leaf: first primitive
    uint32_t count;  // kInner for an inner node, else the leaf's primitive count
    static constexpr uint32_t kInner = ~0u;
};

class Octree final : public Accel {
public:
    explicit Octree(const Geometry& geometry);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override {
        return nodes_.size() * sizeof(OctreeNode) + prims_.size() * sizeof(uint32_t);
    }

    const std::vector<OctreeNode>& nodes() const { return nodes_; }
    int depth() const { return depth_; }

private:
    /// Visits the leaves the ray enters before `tmax` (read again at every step: the closest
    /// hit so far), nearest first; `visit(first, last)` gets a leaf's range of prims_ and
    /// returns true to stop.
    template <class Visit>
    void walk(const Ray& ray, const float& tmax, Visit&& visit) const;
    void build(uint32_t node, const Bounds3& box, std::vector<uint32_t>& ids,
               const std::vector<Bounds3>& bounds, int depth);

    const Geometry& geometry_;
    Bounds3 bounds_;
    std::vector<OctreeNode> nodes_;
    std::vector<uint32_t> prims_;
    int depth_ = 0;
    int64_t reference_budget_ = 0;  // duplicates the build may still add
};

}  // namespace svetlo
