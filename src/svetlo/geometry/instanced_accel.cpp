#include "svetlo/geometry/instanced_accel.h"

#include <algorithm>

#include "svetlo/geometry/ray_box.h"

namespace svetlo {

InstancedAccel::InstancedAccel(const Geometry& geometry, std::unique_ptr<Accel> world,
                               std::vector<std::unique_ptr<Accel>> prototypes)
    : geometry_(geometry), world_(std::move(world)), prototypes_(std::move(prototypes)) {
    std::vector<Bounds3> boxes;
    for (uint32_t k = 0; k < geometry.placements.size(); ++k) {
        boxes.push_back(geometry.placements[k].bounds);
        if (!boxes.back().empty()) order_.push_back(k);  // an empty prototype is never met
    }
    nodes_.reserve(2 * order_.size());
    if (!order_.empty()) build(0, static_cast<uint32_t>(order_.size()), boxes);
}

// The top level splits at the median of the boxes' centres along their widest axis: the
// placements are few beside the triangles, and a scene places them spread out.
uint32_t InstancedAccel::build(uint32_t begin, uint32_t end, const std::vector<Bounds3>& boxes) {
    const auto node = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    Bounds3 box, centres;
    for (uint32_t k = begin; k < end; ++k) {
        box.extend(boxes[order_[k]]);
        centres.extend(boxes[order_[k]].center());
    }
    nodes_[node].box = box;
    if (end - begin <= 2) {
        nodes_[node].a = begin;
        nodes_[node].count = end - begin;
        return node;
    }
    const int axis = max_dimension(centres.extent());
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(
        order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
        [&](uint32_t a, uint32_t b) { return boxes[a].center()[axis] < boxes[b].center()[axis]; });
    const uint32_t left = build(begin, mid, boxes);
    const uint32_t right = build(mid, end, boxes);
    nodes_[node].a = left;
    nodes_[node].b = right;
    return node;
}

template <class F>
void InstancedAccel::visit(const Ray& ray, const float& tmax, uint32_t* visited, F&& f) const {
    if (nodes_.empty()) return;
    const vec3 inv = safe_inverse(ray.d);
    // Each node's box is tested once, when it is pushed; its entry distance goes with it, and
    // a node whose entry lies past a tmax shrunk since is passed by (conservatively: the
    // test's own rounding allowance kept).
    struct Entry {
        uint32_t node;
        float t;
    };
    Entry stack[64];
    int size = 0;
    const auto test = [&](uint32_t node) {
        if (visited) ++*visited;
        const Bounds3& b = nodes_[node].box;
        return Entry{node, box_entry(b.min, b.max, ray.o, inv, tmax)};
    };
    if (const Entry root = test(0); root.t != kInfinity) stack[size++] = root;
    while (size > 0) {
        const Entry e = stack[--size];
        if (e.t > tmax * kSlabRobust) continue;
        const Node& n = nodes_[e.node];
        if (n.count > 0) {
            for (uint32_t k = 0; k < n.count; ++k)
                if (!f(order_[n.a + k])) return;
            continue;
        }
        // The nearer child is visited first (pushed last), so that tmax shrinks early.
        const Entry l = test(n.a), r = test(n.b);
        const bool left_first = l.t <= r.t;
        for (const Entry& c : {left_first ? r : l, left_first ? l : r})
            if (c.t != kInfinity) stack[size++] = c;
    }
}

template <class Intersect>
bool InstancedAccel::closest(const Ray& ray, Hit& hit, uint32_t* visited,
                             Intersect&& intersect) const {
    bool found = intersect(*world_, ray, hit);
    float best = found ? hit.t : ray.tmax;
    visit(ray, best, visited, [&](uint32_t k) {
        const Placement& place = geometry_.placements[k];
        Ray local = place.to_prototype_ray(ray);
        local.tmax = best;
        Hit h;
        if (intersect(*prototypes_[place.prototype], local, h)) {
            hit = h;
            hit.instance = k;
            best = h.t;
            found = true;
        }
        return true;
    });
    return found;
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
    if (world_->occluded(ray)) return true;
    bool blocked = false;
    visit(ray, ray.tmax, nullptr, [&](uint32_t k) {
        const Placement& place = geometry_.placements[k];
        blocked = prototypes_[place.prototype]->occluded(place.to_prototype_ray(ray));
        return !blocked;
    });
    return blocked;
}

size_t InstancedAccel::memory_bytes() const {
    size_t bytes =
        world_->memory_bytes() + nodes_.size() * sizeof(Node) + order_.size() * sizeof(uint32_t);
    for (const auto& p : prototypes_) bytes += p->memory_bytes();
    return bytes;
}

}  // namespace svetlo
