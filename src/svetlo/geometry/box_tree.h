// A wide tree over boxes whose contents are the caller's: the top level of instances
// (InstancedAccel), where each box is a placement of a prototype. It is the wide BVH's node
// (WideBvhNode, eight lanes tested in one AVX2 sequence where the processor has AVX2, else
// four) and its traversal (wide_bvh_traversal.inc), with one box per leaf; the caller tests
// what a leaf's box holds. Built top-down by the binned SAH straight into wide nodes: a node's
// children are found by splitting its boxes in two, then the largest part in two again, until
// it has W parts (docs/geometry.md, "Instances").
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "svetlo/geometry/wide_bvh.h"

namespace svetlo {

/// What a traversal asks of a leaf: test(context, box, hit) tests what box `box` holds against
/// the ray, up to hit.t, and returns whether it found a hit (nearer than hit.t, which it then
/// sets). Any-hit traversals pass a Hit they do not read.
struct BoxLeafTest {
    bool (*test)(const void* context, uint32_t box, Hit& hit);
    const void* context;
};

class BoxTree {
public:
    /// Over the boxes that are not empty (an empty one is never visited). `width` 8 or 4; 0:
    /// eight where WideBvh::eight_wide_available(), else four (as 8 is where it is not).
    explicit BoxTree(std::span<const Bounds3> boxes, int width = 0);

    /// The closest hit among the leaves whose boxes the ray enters before hit.t, nearer boxes
    /// first; `leaf` is called for each until none is left nearer than hit.t. `visited`, when
    /// given, counts the nodes whose boxes were tested. hit.t must hold the ray's tmax.
    template <class Leaf>
    bool closest(const Ray& ray, Hit& hit, Leaf&& leaf, uint32_t* visited = nullptr) const {
        const auto call = [](const void* context, uint32_t box, Hit& h) {
            return (*static_cast<const std::remove_reference_t<Leaf>*>(context))(box, h);
        };
        return closest(ray, hit, BoxLeafTest{call, &leaf}, visited);
    }
    /// Whether `leaf(box)` is true for a box the ray enters before ray.tmax (in no order; it
    /// stops at the first).
    template <class Leaf>
    bool any(const Ray& ray, Leaf&& leaf) const {
        const auto call = [](const void* context, uint32_t box, Hit&) {
            return (*static_cast<const std::remove_reference_t<Leaf>*>(context))(box);
        };
        return any(ray, BoxLeafTest{call, &leaf});
    }

    bool closest(const Ray& ray, Hit& hit, BoxLeafTest leaf, uint32_t* visited) const;
    bool any(const Ray& ray, BoxLeafTest leaf) const;

    int width() const { return width_; }
    /// Wide levels from the root to the deepest leaf (0 without boxes).
    int depth() const { return depth_; }
    size_t node_count() const { return nodes4_.size() + nodes8_.size(); }
    size_t memory_bytes() const {
        return nodes4_.size() * sizeof(WideBvhNode<4>) + nodes8_.size() * sizeof(WideBvhNode<8>);
    }

private:
    template <int W>
    uint32_t build(std::span<uint32_t> order, std::span<const Bounds3> boxes,
                   std::vector<WideBvhNode<W>>& nodes, int level);

    int width_ = 4;
    int depth_ = 0;
    std::vector<WideBvhNode<4>> nodes4_;  // one of the two, by width_; empty without boxes
    std::vector<WideBvhNode<8>> nodes8_;
};

namespace wide {
// The traversals over a BoxTree's nodes, in the files that hold the box tests: four wide in
// wide_bvh.cpp (SSE, or the scalar twin), eight wide in wide_bvh_avx2.cpp (only where
// avx2_available()).
bool boxes_closest4(const WideBvhNode<4>* nodes, const Ray& ray, Hit& hit, BoxLeafTest leaf,
                    uint32_t* visited);
bool boxes_any4(const WideBvhNode<4>* nodes, const Ray& ray, BoxLeafTest leaf);
bool boxes_closest8(const WideBvhNode<8>* nodes, const Ray& ray, Hit& hit, BoxLeafTest leaf,
                    uint32_t* visited);
bool boxes_any8(const WideBvhNode<8>* nodes, const Ray& ray, BoxLeafTest leaf);
}  // namespace wide

}  // namespace svetlo
