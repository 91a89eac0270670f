// A wide BVH: the binned-SAH binary BVH collapsed so that each node holds the boxes of up to
// W children side by side (structure of arrays), tested against a ray in one SIMD
// instruction sequence (Wald, Benthin and Boulos, "Getting Rid of Packets", IEEE RT 2008;
// Dammertz et al., "Shallow Bounding Volume Hierarchies", EGSR 2008). W is 8 with AVX2 where
// the processor has it (chosen at run time: wide_bvh_avx2.cpp), else 4 with SSE; 16 with
// AVX-512 when asked for (`bvh16`, wide_bvh_avx512.cpp; docs/performance.md measures it). A leaf's
// triangles are copied into packets of four (structure of arrays) and tested four at a time
// with the same watertight test, operation for operation, so the hits are bit-identical to
// the scalar test's (eight-wide packets under eight-wide nodes were no faster, leaves holding
// at most eight triangles, and took 60 % more memory); its analytic shapes are tested one by
// one. This is svetlo's fastest structure (`bvh`, the widest the processor runs; `bvh4` is
// the four-wide one everywhere).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/bvh.h"

namespace svetlo {

/// A child reference of a wide node: a node index, or (bit 31 set) an index into the leaves;
/// kWideEmpty in a lane without a child (its box is +inf..-inf, which no ray enters).
inline constexpr uint32_t kWideLeaf = 1u << 31;
inline constexpr uint32_t kWideEmpty = ~0u;

template <int W>
struct alignas(64) WideBvhNode {
    float box[6][W];    // per child lane: min x, min y, min z, max x, max y, max z
    uint32_t child[W];  // a node index, a leaf (kWideLeaf | index) or kWideEmpty
};

/// Four triangles side by side: vertex j's component c of lane k is v[3 j + c][k].
struct alignas(16) TrianglePacket {
    float v[9][4];
    uint32_t id[4];  // primitive ids; ~0 marks an unused lane
};

class WideBvh final : public Accel {
public:
    /// `width` 4, 8 or 16; 0 = 8 where the processor has AVX2, else 4. 16 needs AVX-512 (else
    /// it is 0's width).
    explicit WideBvh(const Geometry& geometry, int threads = 0, int width = 0);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    /// Four and eight wide; the sixteen-wide traversal has no filtered query.
    bool filters_hits() const override { return width_ != 16; }
    bool occluded_if(const Ray& ray, HitFilter counts) const override;
    /// Up to 64 rays at a time, cut into packets that sweep narrow shafts, each traversed once
    /// (occluded_shafts, wide_bvh_traversal.inc); the leaves ray by ray. 16 lanes: ray by ray.
    void occluded_toward(vec3 end, const Ray* rays, size_t count, bool* blocked,
                         const PrimitiveRange* skip = nullptr) const override;
    bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
    bool counts_cost() const override { return true; }
    size_t memory_bytes() const override {
        return nodes4_.size() * sizeof(WideBvhNode<4>) + nodes8_.size() * sizeof(WideBvhNode<8>) +
               nodes16_.size() * sizeof(WideBvhNode<16>) + leaves_.size() * sizeof(Leaf) +
               packets_.size() * sizeof(TrianglePacket) + shapes_.size() * sizeof(uint32_t);
    }
    int width() const { return width_; }

    /// True when this build of svetlo has the eight-wide traversal and the processor runs it.
    static bool eight_wide_available();
    /// The same for the sixteen-wide one (AVX-512).
    static bool sixteen_wide_available();

private:
    struct Leaf {
        uint32_t first_packet, packets;
        uint32_t first_shape, shapes;
        uint32_t lowest, highest;  // the least and the greatest of its primitives' ids
    };
    /// Makes room for a leaf over `prims` (its packets and shapes, after the leaves before it)
    /// and returns its child reference; fill_leaf fills it.
    uint32_t add_leaf(std::span<const uint32_t> prims);
    void fill_leaf(size_t index);
    template <int W>
    void build(const Bvh& bin, LargeArray<WideBvhNode<W>>& nodes, size_t inner);
    template <int W>
    void collapse(std::span<const BvhNode> bin, std::span<const uint32_t> prims, uint32_t b,
                  uint32_t w, LargeArray<WideBvhNode<W>>& nodes);
    /// The primitives a test of leaf `index` tests: four per packet, and its shapes.
    uint32_t leaf_lanes(uint32_t index) const {
        return 4 * leaves_[index].packets + leaves_[index].shapes;
    }
    // The eight-wide traversal (wide_bvh_avx2.cpp); with `cost`, counting its work.
    bool intersect8(const Ray& ray, Hit& hit, TraversalCost* cost = nullptr) const;
    bool occluded8(const Ray& ray) const;
    bool occluded8_if(const Ray& ray, HitFilter counts) const;
    /// The rays (bits) of a packet of at most 64 toward `end` that something blocks.
    uint64_t occluded_toward8(vec3 end, const Ray* rays, size_t count,
                              const PrimitiveRange* skip) const;
    // The sixteen-wide traversal (wide_bvh_avx512.cpp).
    bool intersect16(const Ray& ray, Hit& hit, TraversalCost* cost = nullptr) const;
    bool occluded16(const Ray& ray) const;

    const Geometry& geometry_;
    int width_ = 4;
    // Sized for the worst case before the collapse, then truncated (see LargeArray). One of
    // the two node arrays is used, by width_.
    LargeArray<WideBvhNode<4>> nodes4_;
    LargeArray<WideBvhNode<8>> nodes8_;
    LargeArray<WideBvhNode<16>> nodes16_;
    LargeArray<Leaf> leaves_;
    LargeArray<TrianglePacket> packets_;
    LargeArray<uint32_t> shapes_;  // ids of the leaves' analytic shapes
    size_t node_count_ = 0, leaf_count_ = 0, packet_count_ = 0, shape_count_ = 0;
    std::vector<std::span<const uint32_t>> leaf_prims_;  // each leaf's primitives, while building
    bool empty_ = true;
};

}  // namespace svetlo
