#include "svetlo/geometry/instanced_accel.h"

namespace svetlo {

namespace {

std::vector<Bounds3> placement_boxes(const Geometry& geometry) {
    std::vector<Bounds3> boxes;
    boxes.reserve(geometry.placements.size());
    for (const Placement& p : geometry.placements) boxes.push_back(p.bounds);
    return boxes;
}

}  // namespace

InstancedAccel::InstancedAccel(const Geometry& geometry, std::unique_ptr<Accel> world,
                               std::vector<std::unique_ptr<Accel>> prototypes)
    : geometry_(geometry),
      world_(std::move(world)),
      prototypes_(std::move(prototypes)),
      top_(placement_boxes(geometry)) {}

template <class Intersect>
bool InstancedAccel::closest(const Ray& ray, Hit& hit, uint32_t* visited,
                             Intersect&& intersect) const {
    bool found = intersect(*world_, ray, hit);
    if (!found) {
        hit = Hit{};
        hit.t = ray.tmax;
    }
    // A placement's leaf is asked up to the closest hit so far, in its prototype's space.
    const auto placed = [&](uint32_t k, Hit& best) {
        const Placement& place = geometry_.placements[k];
        Ray local = place.to_prototype_ray(ray);
        local.tmax = best.t;
        Hit h;
        if (!intersect(*prototypes_[place.prototype], local, h)) return false;
        best = h;
        best.instance = k;
        return true;
    };
    return top_.closest(ray, hit, placed, visited) || found;
}

bool InstancedAccel::intersect(const Ray& ray, Hit& hit) const {
    return closest(ray, hit, nullptr,
                   [](const Accel& a, const Ray& r, Hit& h) { return a.intersect(r, h); });
}

bool InstancedAccel::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
    return closest(ray, hit, &cost.nodes, [&](const Accel& a, const Ray& r, Hit& h) {
        return a.intersect_cost(r, h, cost);
    });
}

bool InstancedAccel::counts_cost() const {
    bool all = world_->counts_cost();
    for (const auto& p : prototypes_) all = all && p->counts_cost();
    return all;
}

bool InstancedAccel::occluded(const Ray& ray) const {
    return world_->occluded(ray) || top_.any(ray, [&](uint32_t k) {
        const Placement& place = geometry_.placements[k];
        return prototypes_[place.prototype]->occluded(place.to_prototype_ray(ray));
    });
}

size_t InstancedAccel::memory_bytes() const {
    size_t bytes = world_->memory_bytes() + top_.memory_bytes();
    for (const auto& p : prototypes_) bytes += p->memory_bytes();
    return bytes;
}

}  // namespace svetlo
