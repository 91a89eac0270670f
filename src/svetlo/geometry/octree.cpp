#include "svetlo/geometry/octree.h"

#include <algorithm>

#include "svetlo/geometry/ray_box.h"

namespace svetlo {

namespace {

constexpr uint32_t kMaxLeaf = 8;
constexpr int kMaxDepth = 16;
// Splitting stops where the children would list more than this many times the node's
// primitives (large primitives straddling every split).
constexpr size_t kMaxDuplication = 4;
constexpr int kStackSize = 8 * kMaxDepth + 8;
constexpr int64_t kMaxExtraReferences = 32 << 20;  // duplicated entries, all splits together

Bounds3 child_box(const Bounds3& box, int child) {
    vec3 mid = 0.5f * (box.min + box.max);
    Bounds3 b;
    for (int a = 0; a < 3; ++a) {
        bool upper = (child >> a) & 1;
        b.min[a] = upper ? mid[a] : box.min[a];
        b.max[a] = upper ? box.max[a] : mid[a];
    }
    return b;
}

}  // namespace

Octree::Octree(const Geometry& geometry) : geometry_(geometry) {
    std::vector<uint32_t> all = geometry.bounded_primitives();
    if (all.empty()) return;
    // Bounds indexed by primitive id (unbounded planes keep an empty box).
    std::vector<Bounds3> bounds(geometry.primitive_count());
    for (uint32_t id : all) {
        bounds[id] = geometry.primitive_bounds(id);
        bounds_.extend(bounds[id]);
    }
    widen_box(bounds_.min, bounds_.max);
    reference_budget_ = kMaxExtraReferences;
    nodes_.push_back({});
    build(0, bounds_, all, bounds, 1);
}

void Octree::build(uint32_t node, const Bounds3& box, std::vector<uint32_t>& ids,
                   const std::vector<Bounds3>& bounds, int depth) {
    depth_ = std::max(depth_, depth);
    auto make_leaf = [&] {
        nodes_[node] = {static_cast<uint32_t>(prims_.size()), static_cast<uint32_t>(ids.size())};
        prims_.insert(prims_.end(), ids.begin(), ids.end());
    };
    if (ids.size() <= kMaxLeaf || depth >= kMaxDepth) return make_leaf();
    // Each primitive goes to the children its bounds overlap: per axis the lower half, the
    // upper half or both (the same closed-interval test as child_box with overlaps).
    // Counted first, then filled, so that each list is allocated once.
    std::vector<uint32_t> children[8];
    size_t listed = 0;
    vec3 mid = 0.5f * (box.min + box.max);
    auto distribute = [&](auto&& add) {
        for (uint32_t id : ids) {
            const Bounds3& b = bounds[id];
            int lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                lo[a] = b.min[a] <= mid[a] ? 0 : 1;
                hi[a] = b.max[a] >= mid[a] ? 1 : 0;
            }
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) add(x | (y << 1) | (z << 2), id);
        }
    };
    size_t counts[8] = {};
    distribute([&](int c, uint32_t) { counts[c]++; });
    for (int c = 0; c < 8; ++c) listed += counts[c];
    bool progress = std::any_of(counts, counts + 8, [&](size_t c) { return c < ids.size(); });
    if (!progress || listed > kMaxDuplication * ids.size()) return make_leaf();
    // The duplicates of all splits share one budget, which bounds the memory on any input.
    auto extra = static_cast<int64_t>(listed - ids.size());
    if (extra > reference_budget_) return make_leaf();
    reference_budget_ -= extra;
    for (int c = 0; c < 8; ++c) children[c].reserve(counts[c]);
    distribute([&](int c, uint32_t id) { children[c].push_back(id); });
    std::vector<uint32_t>().swap(ids);  // free the parent's list before recursing
    auto first = static_cast<uint32_t>(nodes_.size());
    nodes_[node] = {first, OctreeNode::kInner};
    nodes_.resize(nodes_.size() + 8);
    for (int c = 0; c < 8; ++c) build(first + c, child_box(box, c), children[c], bounds, depth + 1);
}

namespace {

struct OctreeEntry {
    uint32_t node;
    float t;
    Bounds3 box;
};

/// Pushes the children of `e` that the ray enters before tmax, nearest on top.
template <class Nodes>
void push_children(const Nodes& nodes, const OctreeEntry& e, const Ray& ray, vec3 inv_d, float tmax,
                   OctreeEntry* stack, int& sp) {
    OctreeEntry found[8];
    int n = 0;
    for (int c = 0; c < 8; ++c) {
        uint32_t child = nodes[e.node].first + c;
        if (nodes[child].count == 0) continue;
        Bounds3 b = child_box(e.box, c);
        float t = box_entry(b.min, b.max, ray.o, inv_d, tmax);
        if (t == kInfinity) continue;
        int k = n++;
        while (k > 0 && found[k - 1].t < t) {  // sorted by decreasing entry
            found[k] = found[k - 1];
            --k;
        }
        found[k] = {child, t, b};
    }
    for (int k = 0; k < n; ++k) stack[sp++] = found[k];
}

}  // namespace

template <class Visit>
void Octree::walk(const Ray& ray, const float& tmax, Visit&& visit) const {
    if (nodes_.empty()) return;
    vec3 inv_d = safe_inverse(ray.d);
    float t = box_entry(bounds_.min, bounds_.max, ray.o, inv_d, tmax);
    if (t == kInfinity) return;
    OctreeEntry stack[kStackSize];
    int sp = 0;
    stack[sp++] = {0, t, bounds_};
    while (sp > 0) {
        OctreeEntry e = stack[--sp];
        if (e.t > tmax) continue;  // a closer hit was found since this entry was pushed
        const OctreeNode& node = nodes_[e.node];
        if (node.count == OctreeNode::kInner) {
            push_children(nodes_, e, ray, inv_d, tmax, stack, sp);
        } else if (visit(node.first, node.first + node.count)) {
            return;
        }
    }
}

bool Octree::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    RayPrecomputed pre(ray);
    bool found = false;
    walk(ray, hit.t, [&](uint32_t first, uint32_t last) {
        found |= geometry_.intersect(prims_.data() + first, last - first, ray, pre, hit);
        return false;
    });
    return found;
}

bool Octree::occluded(const Ray& ray) const {
    RayPrecomputed pre(ray);
    bool found = false;
    walk(ray, ray.tmax, [&](uint32_t first, uint32_t last) {
        found = geometry_.occludes(prims_.data() + first, last - first, ray, pre);
        return found;
    });
    return found;
}

}  // namespace svetlo
