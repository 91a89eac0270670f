#include "svetlo/geometry/bvh.h"

#include <utility>

#include "svetlo/geometry/bvh_build.h"
#include "svetlo/geometry/ray_box.h"

namespace svetlo {

namespace {

constexpr int kStackSize = 128;  // > the build's median depth + log2(2^32)

inline float node_entry(const BvhNode& node, vec3 o, vec3 inv_d, float tmax) {
    return box_entry(node.min, node.max, o, inv_d, tmax);
}

}  // namespace

Bvh::Bvh(const Geometry& geometry, int threads) : geometry_(geometry) {
    BvhBuild build = build_bvh(geometry, threads);
    nodes_ = std::move(build.nodes);
    prims_ = std::move(build.prims);
    depth_ = build.depth;
}

bool Bvh::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    if (nodes_.empty()) return false;
    RayPrecomputed pre(ray);
    vec3 inv_d = safe_inverse(ray.d);
    struct Entry {
        uint32_t node;
        float t;
    };
    Entry stack[kStackSize];
    int sp = 0;
    if (node_entry(nodes_[0], ray.o, inv_d, hit.t) == kInfinity) return false;
    stack[sp++] = {0, 0.0f};
    bool found = false;
    while (sp > 0) {
        Entry e = stack[--sp];
        // A closer hit was found since this node was pushed (its entry rounded as the box
        // test rounds its exit: ray_box.h).
        if (e.t > hit.t * kSlabRobust) continue;
        const BvhNode* node = &nodes_[e.node];
        while (node->count == 0) {
            const BvhNode& l = nodes_[node->first];
            const BvhNode& r = nodes_[node->first + 1];
            float tl = node_entry(l, ray.o, inv_d, hit.t);
            float tr = node_entry(r, ray.o, inv_d, hit.t);
            if (tl == kInfinity && tr == kInfinity) {
                node = nullptr;
                break;
            }
            if (tl <= tr) {
                if (tr != kInfinity) stack[sp++] = {node->first + 1, tr};
                node = &l;
            } else {
                if (tl != kInfinity) stack[sp++] = {node->first, tl};
                node = &r;
            }
        }
        if (!node) continue;
        found |= geometry_.intersect(prims_.data() + node->first, node->count, ray, pre, hit);
    }
    return found;
}

bool Bvh::occluded(const Ray& ray) const {
    if (nodes_.empty()) return false;
    RayPrecomputed pre(ray);
    vec3 inv_d = safe_inverse(ray.d);
    uint32_t stack[kStackSize];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const BvhNode& node = nodes_[stack[--sp]];
        if (node_entry(node, ray.o, inv_d, ray.tmax) == kInfinity) continue;
        if (node.count == 0) {
            stack[sp++] = node.first + 1;
            stack[sp++] = node.first;
            continue;
        }
        if (geometry_.occludes(prims_.data() + node.first, node.count, ray, pre)) return true;
    }
    return false;
}

}  // namespace svetlo
