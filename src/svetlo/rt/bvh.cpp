#include "svetlo/rt/bvh.h"

#include <immintrin.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <memory>

#include "svetlo/core/parallel.h"

namespace svetlo {

namespace {

constexpr int kBins = 16;
constexpr uint32_t kMaxLeaf = 8;
constexpr float kTraversalCost = 1.0f;     // relative to one primitive test
constexpr int kMedianDepth = 64;           // below this depth, split at the median
constexpr uint32_t kParallelGrain = 4096;  // smaller subtrees are built serially
constexpr int kStackSize = 128;            // > kMedianDepth + log2(2^32)

/// A primitive during the build: its bounds and id, 32 bytes, partitioned in place.
struct BuildRef {
    vec3 min;
    uint32_t id;
    vec3 max;
    float pad;
    vec3 centroid() const { return 0.5f * (min + max); }
};

class Builder {
public:
    Builder(std::vector<BuildRef>& refs, BvhNode* nodes) : refs_(refs), nodes_(nodes) {}

    uint32_t node_count() const { return node_count_.load(); }
    int depth() const { return depth_.load(); }

    void build_root(const Bounds3& bounds, const Bounds3& centroids) {
        node_count_ = 1;
        build(0, 0, static_cast<uint32_t>(refs_.size()), bounds, centroids, 1);
        group_.wait();
    }

private:
    void make_leaf(uint32_t node, uint32_t begin, uint32_t end, const Bounds3& bounds) {
        nodes_[node] = BvhNode{bounds.min, begin, bounds.max, end - begin};
    }

    void build(uint32_t node, uint32_t begin, uint32_t end, Bounds3 bounds, Bounds3 centroids,
               int depth) {
        int seen = depth_.load();
        while (depth > seen && !depth_.compare_exchange_weak(seen, depth)) {
        }
        uint32_t n = end - begin;
        if (n <= 1) return make_leaf(node, begin, end, bounds);
        vec3 extent = centroids.extent();
        uint32_t mid = begin;
        Bounds3 lb, rb, lc, rc;
        if (max_component(extent) <= 0.0f) {
            // All centroids coincide: no split can separate them.
            if (n <= kMaxLeaf) return make_leaf(node, begin, end, bounds);
            mid = begin + n / 2;
            bounds_of(begin, mid, lb, lc);
            bounds_of(mid, end, rb, rc);
        } else if (depth >= kMedianDepth) {
            int axis = max_dimension(extent);
            mid = begin + n / 2;
            std::nth_element(refs_.begin() + begin, refs_.begin() + mid, refs_.begin() + end,
                             [axis](const BuildRef& a, const BuildRef& b) {
                                 return a.centroid()[axis] < b.centroid()[axis];
                             });
            bounds_of(begin, mid, lb, lc);
            bounds_of(mid, end, rb, rc);
        } else if (!sah_split(begin, end, bounds, centroids, mid, lb, rb, lc, rc)) {
            return make_leaf(node, begin, end, bounds);
        }
        uint32_t left = node_count_.fetch_add(2);
        nodes_[node] = BvhNode{bounds.min, left, bounds.max, 0};
        if (n >= kParallelGrain) {
            group_.run([=, this] { build(left, begin, mid, lb, lc, depth + 1); });
            build(left + 1, mid, end, rb, rc, depth + 1);
        } else {
            build(left, begin, mid, lb, lc, depth + 1);
            build(left + 1, mid, end, rb, rc, depth + 1);
        }
    }

    void bounds_of(uint32_t begin, uint32_t end, Bounds3& bounds, Bounds3& centroids) const {
        bounds = Bounds3{};
        centroids = Bounds3{};
        for (uint32_t k = begin; k < end; ++k) {
            bounds.extend(refs_[k].min);
            bounds.extend(refs_[k].max);
            centroids.extend(refs_[k].centroid());
        }
    }

    /// Bins the centroids along the axis of largest centroid extent, chooses the cheapest of
    /// the kBins - 1 bin boundaries by SAH and partitions refs there. Returns false when a
    /// leaf is cheaper and allowed. Binning one axis (Wald 2007) costs a third of binning
    /// three and loses little quality; the bins' bounds are kept in SSE registers.
    bool sah_split(uint32_t begin, uint32_t end, const Bounds3& bounds, const Bounds3& centroids,
                   uint32_t& mid, Bounds3& lb, Bounds3& rb, Bounds3& lc, Bounds3& rc) {
        uint32_t n = end - begin;
        int a = max_dimension(centroids.extent());
        float cmin = centroids.min[a];
        float scale = static_cast<float>(kBins) * 0.99999f / centroids.extent()[a];
        __m128 bin_min[kBins], bin_max[kBins];
        uint32_t bin_count[kBins] = {};
        for (int b = 0; b < kBins; ++b) {
            bin_min[b] = _mm_set1_ps(kInfinity);
            bin_max[b] = _mm_set1_ps(-kInfinity);
        }
        const BuildRef* refs = refs_.data();
        for (uint32_t k = begin; k < end; ++k) {
            const BuildRef& r = refs[k];
            float c = 0.5f * (r.min[a] + r.max[a]);
            int b = std::min(kBins - 1, static_cast<int>((c - cmin) * scale));
            // Lane 3 holds the id or padding bits: never read back.
            bin_min[b] = _mm_min_ps(bin_min[b], _mm_loadu_ps(&r.min.x));
            bin_max[b] = _mm_max_ps(bin_max[b], _mm_loadu_ps(&r.max.x));
            bin_count[b]++;
        }
        // Sweep from the right, then from the left: cost of splitting after bin b.
        float right_cost[kBins];
        __m128 acc_min = _mm_set1_ps(kInfinity), acc_max = _mm_set1_ps(-kInfinity);
        auto area = [](__m128 lo, __m128 hi) {
            alignas(16) float e[4];
            _mm_store_ps(e, _mm_sub_ps(hi, lo));
            return e[0] < 0.0f ? 0.0f : 2.0f * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
        };
        uint32_t count = 0;
        for (int b = kBins - 1; b > 0; --b) {
            acc_min = _mm_min_ps(acc_min, bin_min[b]);
            acc_max = _mm_max_ps(acc_max, bin_max[b]);
            count += bin_count[b];
            right_cost[b] = count ? area(acc_min, acc_max) * static_cast<float>(count) : 0.0f;
        }
        float best_cost = kInfinity;
        int best_bin = -1;
        acc_min = _mm_set1_ps(kInfinity);
        acc_max = _mm_set1_ps(-kInfinity);
        count = 0;
        for (int b = 0; b < kBins - 1; ++b) {
            acc_min = _mm_min_ps(acc_min, bin_min[b]);
            acc_max = _mm_max_ps(acc_max, bin_max[b]);
            count += bin_count[b];
            if (count == 0 || count == n) continue;
            float cost = area(acc_min, acc_max) * static_cast<float>(count) + right_cost[b + 1];
            if (cost < best_cost) {
                best_cost = cost;
                best_bin = b;
            }
        }
        float node_area = bounds.surface_area();
        float split_cost = kTraversalCost + (node_area > 0.0f ? best_cost / node_area : kInfinity);
        float leaf_cost = static_cast<float>(n);
        if (best_bin < 0 || (n <= kMaxLeaf && leaf_cost <= split_cost)) {
            if (n <= kMaxLeaf) return false;
            // No useful split but too many for a leaf: split at the median index.
            mid = begin + n / 2;
            bounds_of(begin, mid, lb, lc);
            bounds_of(mid, end, rb, rc);
            return true;
        }
        auto it = std::partition(refs_.begin() + begin, refs_.begin() + end, [&](const BuildRef& r) {
            float c = 0.5f * (r.min[a] + r.max[a]);
            return std::min(kBins - 1, static_cast<int>((c - cmin) * scale)) <= best_bin;
        });
        mid = static_cast<uint32_t>(it - refs_.begin());
        // Children's bounds from the bins; their centroid bounds are approximated by the
        // primitive bounds, which contain every centroid (binning only needs a range).
        __m128 l_min = _mm_set1_ps(kInfinity), l_max = _mm_set1_ps(-kInfinity);
        __m128 r_min = l_min, r_max = l_max;
        for (int b = 0; b < kBins; ++b) {
            if (b <= best_bin) {
                l_min = _mm_min_ps(l_min, bin_min[b]);
                l_max = _mm_max_ps(l_max, bin_max[b]);
            } else {
                r_min = _mm_min_ps(r_min, bin_min[b]);
                r_max = _mm_max_ps(r_max, bin_max[b]);
            }
        }
        auto to_bounds = [](__m128 lo, __m128 hi) {
            alignas(16) float l[4], h[4];
            _mm_store_ps(l, lo);
            _mm_store_ps(h, hi);
            return Bounds3{vec3(l[0], l[1], l[2]), vec3(h[0], h[1], h[2])};
        };
        lb = lc = to_bounds(l_min, l_max);
        rb = rc = to_bounds(r_min, r_max);
        return true;
    }

    std::vector<BuildRef>& refs_;
    BvhNode* nodes_;  // room for 2 n - 1 nodes
    std::atomic<uint32_t> node_count_{0};
    std::atomic<int> depth_{0};
    tbb::task_group group_;
};

/// Slab test against a node's box: the entry distance, or infinity on a miss. The exit
/// distance is enlarged by 1 + 2 gamma(3) to cover rounding (pbrt-v4, section 6.8.2).
inline float box_entry(const BvhNode& node, vec3 o, vec3 inv_d, float tmax) {
    constexpr float kRobust = 1.0f + 2.0f * 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f);
    vec3 t0 = (node.min - o) * inv_d, t1 = (node.max - o) * inv_d;
    vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1);
    float enter = std::max(std::max(tn.x, tn.y), std::max(tn.z, 0.0f));
    float exit = std::min(std::min(tf.x, tf.y), std::min(tf.z, tmax)) * kRobust;
    return enter <= exit ? enter : kInfinity;
}

/// 1/d with zero components replaced by a huge finite value of the same sign, so that the
/// slab test never computes 0 * infinity.
inline vec3 safe_inverse(vec3 d) {
    vec3 inv;
    for (int k = 0; k < 3; ++k) inv[k] = d[k] != 0.0f ? 1.0f / d[k] : std::copysign(1e32f, d[k]);
    return inv;
}

}  // namespace

Bvh::Bvh(const Geometry& geometry, int threads) : geometry_(geometry) {
    std::vector<uint32_t> ids = geometry.bounded_primitives();
    if (ids.empty()) return;
    std::vector<BuildRef> refs(ids.size());
    Bounds3 bounds, centroids;
    for (size_t k = 0; k < ids.size(); ++k) {
        Bounds3 b = geometry.primitive_bounds(ids[k]);
        refs[k] = BuildRef{b.min, ids[k], b.max, 0.0f};
        bounds.extend(b);
        centroids.extend(refs[k].centroid());
    }
    // Uninitialised room for the worst case (2 n - 1 nodes): untouched pages cost nothing,
    // and only the nodes built are copied out.
    std::unique_ptr<BvhNode[]> room(new BvhNode[2 * refs.size()]);
    Builder builder(refs, room.get());
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] { builder.build_root(bounds, centroids); });
    nodes_.assign(room.get(), room.get() + builder.node_count());
    depth_ = builder.depth();
    prims_.resize(refs.size());
    for (size_t k = 0; k < refs.size(); ++k) prims_[k] = refs[k].id;
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
    if (box_entry(nodes_[0], ray.o, inv_d, hit.t) == kInfinity) return false;
    stack[sp++] = {0, 0.0f};
    bool found = false;
    while (sp > 0) {
        Entry e = stack[--sp];
        if (e.t > hit.t) continue;  // a closer hit was found since this node was pushed
        const BvhNode* node = &nodes_[e.node];
        while (node->count == 0) {
            const BvhNode& l = nodes_[node->first];
            const BvhNode& r = nodes_[node->first + 1];
            float tl = box_entry(l, ray.o, inv_d, hit.t);
            float tr = box_entry(r, ray.o, inv_d, hit.t);
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
        for (uint32_t k = node->first; k < node->first + node->count; ++k) {
            found |= geometry_.intersect(prims_[k], ray, pre, hit);
        }
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
    Hit hit;
    while (sp > 0) {
        const BvhNode& node = nodes_[stack[--sp]];
        if (box_entry(node, ray.o, inv_d, ray.tmax) == kInfinity) continue;
        if (node.count == 0) {
            stack[sp++] = node.first + 1;
            stack[sp++] = node.first;
            continue;
        }
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
            hit.t = ray.tmax;
            if (geometry_.intersect(prims_[k], ray, pre, hit)) return true;
        }
    }
    return false;
}

}  // namespace svetlo
