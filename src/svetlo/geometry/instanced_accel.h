// The two-level structure of instances (docs/geometry.md, "Instances"): the world's own
// primitives in one structure, each prototype in a structure of its own (built once, in its own
// space, however often it is placed), and a BVH over the placements' boxes on top. A ray that
// reaches a placement's leaf is carried into the prototype's space and traced there with the
// same t, so the closest hit over all of them is the closest in the world.
#pragma once

#include <memory>
#include <vector>

#include "svetlo/geometry/accel.h"

namespace svetlo {

class InstancedAccel final : public Accel {
public:
    /// `world` over geometry's own primitives; `prototypes[k]` over geometry.prototypes[k].
    InstancedAccel(const Geometry& geometry, std::unique_ptr<Accel> world,
                   std::vector<std::unique_ptr<Accel>> prototypes);

    bool intersect(const Ray& ray, Hit& hit) const override;
    bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
    bool counts_cost() const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override;

private:
    /// A node of the top level: a leaf (count > 0) holds placements [a, a + count) of order_,
    /// an inner node its children nodes_[a] and nodes_[b].
    struct Node {
        Bounds3 box;
        uint32_t a = 0, b = 0, count = 0;
    };
    /// The node over order_[begin, end); returns its index.
    uint32_t build(uint32_t begin, uint32_t end, const std::vector<Bounds3>& boxes);
    /// The placements whose boxes the ray enters before `tmax`, nearer nodes first: f(index)
    /// for each until it returns false (tmax is read again after each). Counts the nodes it
    /// visits into `visited` when given.
    template <class F>
    void visit(const Ray& ray, const float& tmax, uint32_t* visited, F&& f) const;
    /// The closest hit of the world and the placements, each asked by `intersect`.
    template <class Intersect>
    bool closest(const Ray& ray, Hit& hit, uint32_t* visited, Intersect&& intersect) const;

    const Geometry& geometry_;
    std::unique_ptr<Accel> world_;
    std::vector<std::unique_ptr<Accel>> prototypes_;
    std::vector<Node> nodes_;
    std::vector<uint32_t> order_;  // placement indices, leaves' ranges into it
};

/// make_accel's step for a geometry with placements: `make` (one entry of the accelerator
/// table) over the world's primitives and over each prototype, under an InstancedAccel.
template <class Make>
std::unique_ptr<Accel> make_instanced_accel(const Geometry& geometry, Make&& make) {
    std::unique_ptr<Accel> world = make(geometry);
    if (!world || geometry.placements.empty()) return world;
    std::vector<std::unique_ptr<Accel>> prototypes;
    for (const auto& p : geometry.prototypes) {
        prototypes.push_back(make(*p));
        if (!prototypes.back()) return nullptr;
    }
    return std::make_unique<InstancedAccel>(geometry, std::move(world), std::move(prototypes));
}

}  // namespace svetlo
