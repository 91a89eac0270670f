// The two-level structure of instances (docs/geometry.md, "Instances"): the world's own
// primitives in one structure, each prototype in a structure of its own (built once, in its own
// space, however often it is placed), and a BVH over the placements' boxes on top. A ray that
// reaches a placement's leaf is carried into the prototype's space and traced there with the
// same t, so the closest hit over all of them is the closest in the world. The top level is a
// BoxTree: the wide BVH's nodes and traversal, one placement per leaf.
#pragma once

#include <memory>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/box_tree.h"

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
    /// The closest hit of the world and the placements, each asked by `intersect`; `visited`
    /// counts the top level's nodes when given.
    template <class Intersect>
    bool closest(const Ray& ray, Hit& hit, uint32_t* visited, Intersect&& intersect) const;

    const Geometry& geometry_;
    std::unique_ptr<Accel> world_;
    std::vector<std::unique_ptr<Accel>> prototypes_;
    BoxTree top_;  // over the placements' boxes, in the world; a leaf is a placement
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
