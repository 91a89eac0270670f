#include "svetlo/rt/wide_bvh.h"

#include <immintrin.h>

#include <stdexcept>

#include "svetlo/rt/bvh.h"
#include "svetlo/rt/ray_box.h"

namespace svetlo {

namespace {

// A child reference: a node index, or a leaf: bit 31 set, bits 28..30 the primitive count
// minus one (leaves hold 1 to 8), bits 0..27 the first primitive.
constexpr uint32_t kLeaf = 1u << 31;
constexpr uint32_t kEmpty = ~0u;
constexpr uint32_t kMaxPrimitives = 1u << 28;
constexpr int kStackSize = 256;

uint32_t leaf_ref(uint32_t first, uint32_t count) { return kLeaf | ((count - 1) << 28) | first; }
uint32_t leaf_first(uint32_t ref) { return ref & (kMaxPrimitives - 1); }
uint32_t leaf_count(uint32_t ref) { return ((ref >> 28) & 7u) + 1; }

float area(const BvhNode& n) {
    vec3 e = n.max - n.min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

/// Collapses the binary tree under `b` into wide node `w`: the largest inner child is opened
/// until four children are gathered (or only leaves remain).
void collapse(std::span<const BvhNode> bin, uint32_t b, std::vector<WideBvhNode>& wide, uint32_t w) {
    uint32_t kids[4] = {bin[b].first, bin[b].first + 1, 0, 0};
    int n = 2;
    while (n < 4) {
        int best = -1;
        float best_area = -1.0f;
        for (int k = 0; k < n; ++k) {
            if (bin[kids[k]].count == 0 && area(bin[kids[k]]) > best_area) {
                best = k;
                best_area = area(bin[kids[k]]);
            }
        }
        if (best < 0) break;
        uint32_t open = kids[best];
        kids[best] = bin[open].first;
        kids[n++] = bin[open].first + 1;
    }
    WideBvhNode node;
    for (int k = 0; k < 4; ++k) {
        for (int a = 0; a < 3; ++a) {
            node.box[a][k] = k < n ? bin[kids[k]].min[a] : kInfinity;
            node.box[a + 3][k] = k < n ? bin[kids[k]].max[a] : -kInfinity;
        }
        node.child[k] = kEmpty;
    }
    for (int k = 0; k < n; ++k) {
        const BvhNode& c = bin[kids[k]];
        if (c.count > 0) {
            node.child[k] = leaf_ref(c.first, c.count);
        } else {
            auto index = static_cast<uint32_t>(wide.size());
            wide.emplace_back();
            node.child[k] = index;
            collapse(bin, kids[k], wide, index);
        }
    }
    wide[w] = node;
}

/// The four children's entry distances; lanes that miss hold +infinity. Returns the hit mask.
struct RayBoxes {
    __m128 o[3], inv[3];
    int near[3], far[3];  // box rows of the near and far planes per axis

    RayBoxes(const Ray& ray) {
        vec3 inv_d = safe_inverse(ray.d);
        for (int a = 0; a < 3; ++a) {
            o[a] = _mm_set1_ps(ray.o[a]);
            inv[a] = _mm_set1_ps(inv_d[a]);
            near[a] = inv_d[a] >= 0.0f ? a : a + 3;
            far[a] = inv_d[a] >= 0.0f ? a + 3 : a;
        }
    }

    int test(const WideBvhNode& n, float tmax, __m128& t_enter) const {
        __m128 tn0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[0]]), o[0]), inv[0]);
        __m128 tn1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[1]]), o[1]), inv[1]);
        __m128 tn2 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[2]]), o[2]), inv[2]);
        __m128 tf0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[0]]), o[0]), inv[0]);
        __m128 tf1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[1]]), o[1]), inv[1]);
        __m128 tf2 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[2]]), o[2]), inv[2]);
        __m128 enter = _mm_max_ps(_mm_max_ps(tn0, tn1), _mm_max_ps(tn2, _mm_setzero_ps()));
        __m128 exit = _mm_min_ps(_mm_min_ps(tf0, tf1), _mm_min_ps(tf2, _mm_set1_ps(tmax)));
        exit = _mm_mul_ps(exit, _mm_set1_ps(kSlabRobust));
        t_enter = enter;
        return _mm_movemask_ps(_mm_cmple_ps(enter, exit));
    }
};

struct Entry {
    uint32_t ref;
    float t;
};

}  // namespace

WideBvh::WideBvh(const Geometry& geometry, int threads) : geometry_(geometry) {
    if (geometry.primitive_count() >= kMaxPrimitives) {
        throw std::runtime_error("the wide BVH holds at most 2^28 primitives");
    }
    Bvh bin(geometry, threads);
    if (bin.nodes().empty()) return;
    empty_ = false;
    prims_.assign(bin.primitives().begin(), bin.primitives().end());
    tris_.resize(3 * prims_.size());
    for (size_t k = 0; k < prims_.size(); ++k) {
        if (!geometry.is_triangle(prims_[k])) continue;
        for (int v = 0; v < 3; ++v) tris_[3 * k + v] = geometry.positions[geometry.indices[3 * size_t{prims_[k]} + v]];
    }
    const BvhNode& root = bin.nodes()[0];
    if (root.count > 0) {
        // A single leaf: one wide node with one child.
        WideBvhNode node;
        for (int k = 0; k < 4; ++k) {
            for (int a = 0; a < 3; ++a) {
                node.box[a][k] = k == 0 ? root.min[a] : kInfinity;
                node.box[a + 3][k] = k == 0 ? root.max[a] : -kInfinity;
            }
            node.child[k] = k == 0 ? leaf_ref(root.first, root.count) : kEmpty;
        }
        nodes_.push_back(node);
        return;
    }
    nodes_.reserve(bin.nodes().size() / 2 + 1);
    nodes_.emplace_back();
    collapse(bin.nodes(), 0, nodes_, 0);
}

bool WideBvh::leaf_intersect(uint32_t ref, const Ray& ray, const RayPrecomputed& pre, Hit& hit) const {
    bool found = false;
    uint32_t first = leaf_first(ref), last = first + leaf_count(ref);
    for (uint32_t k = first; k < last; ++k) {
        uint32_t id = prims_[k];
        if (!geometry_.is_triangle(id)) {
            found |= geometry_.intersect(id, ray, pre, hit);
            continue;
        }
        const vec3* p = &tris_[3 * size_t{k}];
        float t, b1, b2;
        if (intersect_triangle(ray, pre, p[0], p[1], p[2], hit.t, t, b1, b2)) {
            hit.t = t;
            hit.prim = id;
            hit.u = b1;
            hit.v = b2;
            hit.part = 0;
            found = true;
        }
    }
    return found;
}

bool WideBvh::leaf_occluded(uint32_t ref, const Ray& ray, const RayPrecomputed& pre) const {
    uint32_t first = leaf_first(ref), last = first + leaf_count(ref);
    for (uint32_t k = first; k < last; ++k) {
        uint32_t id = prims_[k];
        if (!geometry_.is_triangle(id)) {
            Hit hit;
            hit.t = ray.tmax;
            if (geometry_.intersect(id, ray, pre, hit)) return true;
            continue;
        }
        const vec3* p = &tris_[3 * size_t{k}];
        float t, b1, b2;
        if (intersect_triangle(ray, pre, p[0], p[1], p[2], ray.tmax, t, b1, b2)) return true;
    }
    return false;
}

bool WideBvh::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    if (empty_) return false;
    RayPrecomputed pre(ray);
    RayBoxes boxes(ray);
    Entry stack[kStackSize];
    int sp = 0;
    stack[sp++] = {0, 0.0f};
    bool found = false;
    while (sp > 0) {
        Entry e = stack[--sp];
        if (e.t > hit.t) continue;  // a closer hit was found since this entry was pushed
        uint32_t ref = e.ref;
        for (;;) {
            if (ref & kLeaf) {
                found |= leaf_intersect(ref, ray, pre, hit);
                break;
            }
            const WideBvhNode& node = nodes_[ref];
            alignas(16) float t[4];
            __m128 enter;
            int mask = boxes.test(node, hit.t, enter);
            if (mask == 0) break;
            _mm_store_ps(t, enter);
            // The children hit, sorted by entry distance (at most four: insertion sort).
            Entry hits[4];
            int n = 0;
            for (int k = 0; k < 4; ++k) {
                if (!(mask & (1 << k))) continue;
                int j = n++;
                while (j > 0 && hits[j - 1].t > t[k]) {
                    hits[j] = hits[j - 1];
                    --j;
                }
                hits[j] = {node.child[k], t[k]};
            }
            for (int k = n - 1; k > 0; --k) stack[sp++] = hits[k];
            ref = hits[0].ref;
        }
    }
    return found;
}

bool WideBvh::occluded(const Ray& ray) const {
    if (empty_) return false;
    RayPrecomputed pre(ray);
    RayBoxes boxes(ray);
    uint32_t stack[kStackSize];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        uint32_t ref = stack[--sp];
        if (ref & kLeaf) {
            if (leaf_occluded(ref, ray, pre)) return true;
            continue;
        }
        const WideBvhNode& node = nodes_[ref];
        __m128 enter;
        int mask = boxes.test(node, ray.tmax, enter);
        for (int k = 0; k < 4; ++k) {
            if (mask & (1 << k)) stack[sp++] = node.child[k];
        }
    }
    return false;
}

}  // namespace svetlo
