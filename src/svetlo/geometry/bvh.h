// A bounding volume hierarchy built with the binned surface area heuristic (Wald, "On fast
// Construction of SAH-based Bounding Volume Hierarchies", IEEE RT 2007): 16 bins on the
// axis of largest extent, leaves of at most 8 primitives, subtrees built in parallel (the build
// is bvh_build.cpp). Nodes are 32 bytes; the two children of an inner node are adjacent. Traversal
// visits the nearer child first and skips nodes farther than the closest hit so far.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "svetlo/core/large_array.h"
#include "svetlo/geometry/accel.h"

namespace svetlo {

struct BvhNode {
    vec3 min;
    uint32_t
        first;  // inner node: index of the left child (right = first + 1); leaf: first primitive
    vec3 max;
    uint32_t count;  // 0 for an inner node, else the number of primitives in the leaf
};
static_assert(sizeof(BvhNode) == 32);

class Bvh final : public Accel {
public:
    Bvh(const Geometry& geometry, int threads = 0);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override {
        return nodes_.size() * sizeof(BvhNode) + prims_.size() * sizeof(uint32_t);
    }

    std::span<const BvhNode> nodes() const { return {nodes_.data(), nodes_.size()}; }
    std::span<const uint32_t> primitives() const { return {prims_.data(), prims_.size()}; }
    int depth() const { return depth_; }

private:
    const Geometry& geometry_;
    LargeArray<BvhNode> nodes_;   // room for 2 n - 1 nodes, truncated to those built
    LargeArray<uint32_t> prims_;  // primitive ids in leaf order
    int depth_ = 0;
};

}  // namespace svetlo
