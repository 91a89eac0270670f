// A four-wide BVH: the binned-SAH binary BVH collapsed so that each node holds the boxes of
// up to four children side by side (structure of arrays), tested against a ray in one SSE
// instruction sequence (Wald, Benthin and Boulos, "Getting Rid of Packets", IEEE RT 2008;
// Dammertz et al., "Shallow Bounding Volume Hierarchies", EGSR 2008). Leaves keep the
// binary BVH's primitive ranges; the triangles' vertices are copied in leaf order so that a
// leaf reads one contiguous block. This is svetlo's fastest structure (`bvh`).
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/rt/accel.h"

namespace svetlo {

struct alignas(64) WideBvhNode {
    float box[6][4];     // per child lane: min x, min y, min z, max x, max y, max z
    uint32_t child[4];   // a node index, a leaf (kLeaf bit, see wide_bvh.cpp) or kEmpty
};

class WideBvh final : public Accel {
public:
    explicit WideBvh(const Geometry& geometry, int threads = 0);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override {
        return nodes_.size() * sizeof(WideBvhNode) + prims_.size() * sizeof(uint32_t) +
               tris_.size() * sizeof(vec3);
    }

    const std::vector<WideBvhNode>& nodes() const { return nodes_; }
    const std::vector<uint32_t>& primitives() const { return prims_; }

private:
    bool leaf_intersect(uint32_t ref, const Ray& ray, const RayPrecomputed& pre, Hit& hit) const;
    bool leaf_occluded(uint32_t ref, const Ray& ray, const RayPrecomputed& pre) const;

    const Geometry& geometry_;
    std::vector<WideBvhNode> nodes_;
    std::vector<uint32_t> prims_;  // primitive ids in leaf order
    std::vector<vec3> tris_;       // 3 vertices per entry of prims_ (unused for shapes)
    bool empty_ = true;
};

}  // namespace svetlo
