// A four-wide BVH: the binned-SAH binary BVH collapsed so that each node holds the boxes of
// up to four children side by side (structure of arrays), tested against a ray in one SSE
// instruction sequence (Wald, Benthin and Boulos, "Getting Rid of Packets", IEEE RT 2008;
// Dammertz et al., "Shallow Bounding Volume Hierarchies", EGSR 2008). A leaf's triangles are
// copied into packets of four (structure of arrays) and tested four at a time with the same
// watertight test, operation for operation, so the hits are bit-identical to the scalar
// test's; its analytic shapes are tested one by one. This is svetlo's fastest structure (`bvh`).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/bvh.h"

namespace svetlo {

struct alignas(64) WideBvhNode {
    float box[6][4];    // per child lane: min x, min y, min z, max x, max y, max z
    uint32_t child[4];  // a node index, a leaf (kLeaf bit, see wide_bvh.cpp) or kEmpty
};

/// Four triangles side by side: vertex j's component c of lane k is v[3 j + c][k].
struct alignas(16) TrianglePacket {
    float v[9][4];
    uint32_t id[4];  // primitive ids; ~0 marks an unused lane
};

class WideBvh final : public Accel {
public:
    explicit WideBvh(const Geometry& geometry, int threads = 0);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override {
        return nodes_.size() * sizeof(WideBvhNode) + leaves_.size() * sizeof(Leaf) +
               packets_.size() * sizeof(TrianglePacket) + shapes_.size() * sizeof(uint32_t);
    }

    std::span<const WideBvhNode> nodes() const { return {nodes_.data(), nodes_.size()}; }

private:
    struct Leaf {
        uint32_t first_packet, packets;
        uint32_t first_shape, shapes;
    };
    uint32_t add_leaf(std::span<const uint32_t> prims);
    bool leaf_intersect(const Leaf& leaf, const Ray& ray, const RayPrecomputed& pre,
                        Hit& hit) const;
    bool leaf_occluded(const Leaf& leaf, const Ray& ray, const RayPrecomputed& pre) const;
    void collapse(std::span<const BvhNode> bin, std::span<const uint32_t> prims, uint32_t b,
                  uint32_t w);

    const Geometry& geometry_;
    // Sized for the worst case before the collapse, then truncated (see LargeArray).
    LargeArray<WideBvhNode> nodes_;
    LargeArray<Leaf> leaves_;
    LargeArray<TrianglePacket> packets_;
    LargeArray<uint32_t> shapes_;  // ids of the leaves' analytic shapes
    size_t node_count_ = 0, leaf_count_ = 0, packet_count_ = 0, shape_count_ = 0;
    bool empty_ = true;
};

}  // namespace svetlo
