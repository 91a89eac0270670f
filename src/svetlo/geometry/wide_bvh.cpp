// The wide BVH's build and its four-wide traversal. The kernels' plain statement, and what runs
// without SIMD, is wide_bvh_reference.h (ScalarBoxes, ScalarPackets); RayBoxes4 and
// wide_bvh_packets.inc are their SSE forms.
#include "svetlo/geometry/wide_bvh.h"

// The four-wide SSE kernels run on x86-64 (SVETLO_SIMD) and in the browser, where emscripten
// compiles SSE's intrinsics to WebAssembly's 128-bit SIMD, one instruction for each here, with
// SSE's own answers for NaNs (its min and max are a compare and a select), so that the page's
// images stay the native program's (docs/web.md, "Speed and size").
#if SVETLO_SIMD || defined(__wasm_simd128__)
#define SVETLO_SSE_KERNELS 1
#include <immintrin.h>
#else
#define SVETLO_SSE_KERNELS 0
#endif

#include <algorithm>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "svetlo/core/parallel.h"
#include "svetlo/geometry/avx2.h"
#include "svetlo/geometry/box_tree.h"
#include "svetlo/geometry/bvh.h"
#include "svetlo/geometry/ray_box.h"
#include "svetlo/geometry/triangle.h"
#include "svetlo/geometry/wide_bvh_reference.h"

namespace svetlo {

namespace {

#if SVETLO_SSE_KERNELS
#include "svetlo/geometry/wide_bvh_packets.inc"
#endif
#include "svetlo/geometry/wide_bvh_traversal.inc"

float half_area(const BvhNode& n) {
    vec3 e = n.max - n.min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

#if SVETLO_SSE_KERNELS
/// A ray against the four boxes of a node (SSE): returns the mask of children hit and their
/// entry distances. Its twin: wide::ScalarBoxes<4> (wide_bvh_reference.h).
struct RayBoxes4 {
    static constexpr int kWidth = 4;
    __m128 o[3], inv[3];
    int near[3], far[3];  // box rows of the near and far planes per axis

    explicit RayBoxes4(const Ray& ray) {
        vec3 inv_d = safe_inverse(ray.d);
        for (int a = 0; a < 3; ++a) {
            o[a] = _mm_set1_ps(ray.o[a]);
            inv[a] = _mm_set1_ps(inv_d[a]);
            near[a] = inv_d[a] >= 0.0f ? a : a + 3;
            far[a] = inv_d[a] >= 0.0f ? a + 3 : a;
        }
    }

    int test(const WideBvhNode<4>& n, float tmax, float* t_enter) const {
        __m128 tn0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[0]]), o[0]), inv[0]);
        __m128 tn1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[1]]), o[1]), inv[1]);
        __m128 tn2 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[near[2]]), o[2]), inv[2]);
        __m128 tf0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[0]]), o[0]), inv[0]);
        __m128 tf1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[1]]), o[1]), inv[1]);
        __m128 tf2 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.box[far[2]]), o[2]), inv[2]);
        __m128 enter = _mm_max_ps(_mm_max_ps(tn0, tn1), _mm_max_ps(tn2, _mm_setzero_ps()));
        __m128 exit = _mm_min_ps(_mm_min_ps(tf0, tf1), _mm_min_ps(tf2, _mm_set1_ps(tmax)));
        exit = _mm_mul_ps(exit, _mm_set1_ps(kSlabRobust));
        _mm_store_ps(t_enter, enter);
        return _mm_movemask_ps(_mm_cmple_ps(enter, exit));
    }
};
using Boxes4 = RayBoxes4;
using Packets = SsePackets;
#else
using Boxes4 = wide::ScalarBoxes<4>;
using Packets = wide::ScalarPackets;
#endif

}  // namespace

#if SVETLO_SIMD
int wide::boxes_sse(const Ray& ray, const WideBvhNode<4>& node, float tmax, float* t_enter) {
    return RayBoxes4(ray).test(node, tmax, t_enter);
}
bool wide::packets_closest_sse(const Ray& ray, const TrianglePacket* packets, uint32_t count,
                               Hit& hit) {
    const RayPrecomputed pre(ray);
    return SsePackets(ray, pre).closest(packets, count, hit);
}
bool wide::packets_any_sse(const Ray& ray, const TrianglePacket* packets, uint32_t count) {
    const RayPrecomputed pre(ray);
    return SsePackets(ray, pre).any(packets, count);
}

void wide::packets_hits_sse(const Ray& ray, const TrianglePacket* packets, uint32_t count,
                            std::vector<Hit>& asked) {
    const RayPrecomputed pre(ray);
    SsePackets(ray, pre).any_if(packets, count, [&](const Hit& hit) {
        asked.push_back(hit);
        return false;
    });
}
#endif

bool WideBvh::eight_wide_available() { return avx2_available(); }
bool WideBvh::sixteen_wide_available() { return avx512_available(); }

WideBvh::WideBvh(const Geometry& geometry, int threads, int width) : geometry_(geometry) {
    if (width == 16 && sixteen_wide_available()) {
        width_ = 16;
    } else {
        width_ = (width == 0 || width == 8 || width == 16) && eight_wide_available() ? 8 : 4;
    }
    Bvh bin(geometry, threads);
    if (bin.nodes().empty()) return;
    empty_ = false;
    // Exact room: every binary leaf becomes one wide leaf; wide nodes are fewer than binary
    // inner nodes.
    size_t inner = 0, leaves = 0;
    for (const BvhNode& n : bin.nodes()) (n.count == 0 ? inner : leaves)++;
    if (leaves >= kWideLeaf) throw std::runtime_error("the wide BVH holds at most 2^31 leaves");
    leaves_ = LargeArray<Leaf>(leaves);
    leaf_prims_.reserve(leaves);
    if (width_ == 16) {
        build<16>(bin, nodes16_, inner);
    } else if (width_ == 8) {
        build<8>(bin, nodes8_, inner);
    } else {
        build<4>(bin, nodes4_, inner);
    }
    // The leaves' packets and shapes, counted by the collapse, filled in parallel now that
    // each leaf knows its place.
    packets_ = LargeArray<TrianglePacket>(packet_count_);
    shapes_ = LargeArray<uint32_t>(shape_count_);
    with_threads(threads, [&] { parallel_for_each(leaf_count_, [&](size_t k) { fill_leaf(k); }); });
    leaf_prims_ = {};
}

template <int W>
void WideBvh::build(const Bvh& bin, LargeArray<WideBvhNode<W>>& nodes, size_t inner) {
    nodes = LargeArray<WideBvhNode<W>>(std::max<size_t>(inner, 1));
    const BvhNode& root = bin.nodes()[0];
    node_count_ = 1;
    if (root.count > 0) {
        // A single leaf: one wide node with one child.
        WideBvhNode<W> node;
        for (int k = 0; k < W; ++k) {
            for (int a = 0; a < 3; ++a) {
                node.box[a][k] = k == 0 ? root.min[a] : kInfinity;
                node.box[a + 3][k] = k == 0 ? root.max[a] : -kInfinity;
            }
            node.child[k] = kWideEmpty;
        }
        node.child[0] = add_leaf(bin.primitives().subspan(root.first, root.count));
        nodes[0] = node;
    } else {
        collapse<W>(bin.nodes(), bin.primitives(), 0, 0, nodes);
    }
    nodes.truncate(node_count_);
}

uint32_t WideBvh::add_leaf(std::span<const uint32_t> prims) {
    auto triangles = static_cast<uint32_t>(std::count_if(
        prims.begin(), prims.end(), [&](uint32_t id) { return geometry_.is_triangle(id); }));
    auto count = static_cast<uint32_t>(prims.size());
    const auto [lowest, highest] = std::minmax_element(prims.begin(), prims.end());
    leaves_[leaf_count_] = Leaf{static_cast<uint32_t>(packet_count_),
                                (triangles + 3) / 4,
                                static_cast<uint32_t>(shape_count_),
                                count - triangles,
                                *lowest,
                                *highest};
    packet_count_ += (triangles + 3) / 4;
    shape_count_ += count - triangles;
    leaf_prims_.push_back(prims);
    return kWideLeaf | static_cast<uint32_t>(leaf_count_++);
}

void WideBvh::fill_leaf(size_t index) {
    // The leaves' triangles lie wherever the mesh put them, so fetching their vertex indices
    // and then their vertices waits on the memory twice: both are asked for a few leaves
    // ahead (the indices four leaves ahead, the vertices of those asked for before, two).
    if (index + 4 < leaf_count_) {
        for (uint32_t id : leaf_prims_[index + 4])
            if (geometry_.is_triangle(id)) __builtin_prefetch(&geometry_.indices[3 * size_t{id}]);
    }
    if (index + 2 < leaf_count_) {
        for (uint32_t id : leaf_prims_[index + 2]) {
            if (!geometry_.is_triangle(id)) continue;
            for (int j = 0; j < 3; ++j)
                __builtin_prefetch(&geometry_.positions[geometry_.indices[3 * size_t{id} + j]]);
        }
    }
    const Leaf& leaf = leaves_[index];
    uint32_t shape = leaf.first_shape, packet = leaf.first_packet;
    TrianglePacket* p = nullptr;  // taken when a triangle needs it: a leaf may have none
    int lane = 4;
    for (uint32_t id : leaf_prims_[index]) {
        if (!geometry_.is_triangle(id)) {
            shapes_[shape++] = id;
            continue;
        }
        if (lane == 4) {
            p = &packets_[packet++];
            for (auto& row : p->v) std::fill(row, row + 4, 0.0f);
            std::fill(p->id, p->id + 4, ~0u);
            lane = 0;
        }
        for (int j = 0; j < 3; ++j) {
            vec3 q = geometry_.positions[geometry_.indices[3 * size_t{id} + j]];
            for (int c = 0; c < 3; ++c) p->v[3 * j + c][lane] = q[c];
        }
        p->id[lane++] = id;
    }
}

/// Collapses the binary tree under `b` into wide node `w`: the largest inner child is opened
/// until W children are gathered (or only leaves remain).
template <int W>
void WideBvh::collapse(std::span<const BvhNode> bin, std::span<const uint32_t> prims, uint32_t b,
                       uint32_t w, LargeArray<WideBvhNode<W>>& nodes) {
    uint32_t kids[W] = {bin[b].first, bin[b].first + 1};
    int n = 2;
    while (n < W) {
        int best = -1;
        float best_area = -1.0f;
        for (int k = 0; k < n; ++k) {
            if (bin[kids[k]].count == 0 && half_area(bin[kids[k]]) > best_area) {
                best = k;
                best_area = half_area(bin[kids[k]]);
            }
        }
        if (best < 0) break;
        uint32_t open = kids[best];
        kids[best] = bin[open].first;
        kids[n++] = bin[open].first + 1;
    }
    WideBvhNode<W> node;
    for (int k = 0; k < W; ++k) {
        for (int a = 0; a < 3; ++a) {
            node.box[a][k] = k < n ? bin[kids[k]].min[a] : kInfinity;
            node.box[a + 3][k] = k < n ? bin[kids[k]].max[a] : -kInfinity;
        }
        node.child[k] = kWideEmpty;
    }
    for (int k = 0; k < n; ++k) {
        const BvhNode& c = bin[kids[k]];
        if (c.count > 0) {
            node.child[k] = add_leaf(prims.subspan(c.first, c.count));
        } else {
            auto index = static_cast<uint32_t>(node_count_++);
            node.child[k] = index;
            collapse<W>(bin, prims, kids[k], index, nodes);
        }
    }
    nodes[w] = node;
}

bool WideBvh::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    hit.t = ray.tmax;
    if (empty_) return false;
    if (width_ == 16) return intersect16(ray, hit);
    if (width_ == 8) return intersect8(ray, hit);
    const RayPrecomputed pre(ray);
    const Packets test(ray, pre);
    return traverse_closest<Boxes4>(nodes4_.data(), ray, hit, [&](uint32_t leaf) {
        return leaf_closest(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test, hit);
    });
}

bool WideBvh::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
    hit = Hit{};
    hit.t = ray.tmax;
    if (empty_) return false;
    if (width_ == 16) return intersect16(ray, hit, &cost);
    if (width_ == 8) return intersect8(ray, hit, &cost);
    const RayPrecomputed pre(ray);
    const Packets test(ray, pre);
    return traverse_closest<Boxes4>(
        nodes4_.data(), ray, hit,
        [&](uint32_t leaf) {
            cost.primitives += leaf_lanes(leaf);
            return leaf_closest(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test,
                                hit);
        },
        NodeCount{&cost.nodes});
}

bool WideBvh::occluded(const Ray& ray) const {
    if (empty_) return false;
    if (width_ == 16) return occluded16(ray);
    if (width_ == 8) return occluded8(ray);
    const RayPrecomputed pre(ray);
    const Packets test(ray, pre);
    return traverse_any<Boxes4>(nodes4_.data(), ray, [&](uint32_t leaf) {
        return leaf_any(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test);
    });
}

bool WideBvh::occluded_if(const Ray& ray, HitFilter counts) const {
    if (empty_) return false;
    if (width_ == 8) return occluded8_if(ray, counts);
    const RayPrecomputed pre(ray);
    const Packets test(ray, pre);
    const auto counted = [&](const Hit& hit) { return counts(ray, hit); };
    return traverse_any<Boxes4>(nodes4_.data(), ray, [&](uint32_t leaf) {
        return leaf_any_if(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test,
                           counted);
    });
}

void WideBvh::occluded_toward(vec3 end, const Ray* rays, size_t count, bool* blocked,
                              const PrimitiveRange* skip) const {
    if (empty_ || width_ == 16) {
        Accel::occluded_toward(end, rays, count, blocked);
        return;
    }
    constexpr size_t kPacket = 64;  // the bits of a mask
    for (size_t first = 0; first < count; first += kPacket) {
        const size_t n = std::min(kPacket, count - first);
        const Ray* packet = rays + first;
        const PrimitiveRange* packet_skip = skip ? skip + first : nullptr;
        uint64_t hit = 0;
        if (width_ == 8) {
            hit = occluded_toward8(end, packet, n, packet_skip);
        } else {
            hit = occluded_packet<4, Packets>(
                nodes4_.data(), leaves_.data(), packets_.data(), shapes_.data(), geometry_, end,
                packet, n, packet_skip, [&](int m) { return occluded(packet[m]); });
        }
        for (size_t k = 0; k < n; ++k) blocked[first + k] = (hit >> k) & 1;
    }
}

bool wide::boxes_closest4(const WideBvhNode<4>* nodes, const Ray& ray, Hit& hit, BoxLeafTest leaf,
                          uint32_t* visited) {
    const auto test = [&](uint32_t box) { return leaf.test(leaf.context, box, hit); };
    if (visited) return traverse_closest<Boxes4>(nodes, ray, hit, test, NodeCount{visited});
    return traverse_closest<Boxes4>(nodes, ray, hit, test);
}

bool wide::boxes_any4(const WideBvhNode<4>* nodes, const Ray& ray, BoxLeafTest leaf) {
    Hit unread;
    return traverse_any<Boxes4>(nodes, ray,
                                [&](uint32_t box) { return leaf.test(leaf.context, box, unread); });
}

#ifndef SVETLO_HAS_AVX2_BVH
// Never called: width_ is 8 only where eight_wide_available().
bool wide::boxes_closest8(const WideBvhNode<8>*, const Ray&, Hit&, BoxLeafTest, uint32_t*) {
    return false;
}
bool wide::boxes_any8(const WideBvhNode<8>*, const Ray&, BoxLeafTest) { return false; }
bool WideBvh::intersect8(const Ray&, Hit&, TraversalCost*) const { return false; }
bool WideBvh::occluded8(const Ray&) const { return false; }
bool WideBvh::occluded8_if(const Ray&, HitFilter) const { return false; }
uint64_t WideBvh::occluded_toward8(vec3, const Ray*, size_t, const PrimitiveRange*) const {
    return 0;
}
#endif
#ifndef SVETLO_HAS_AVX512_BVH
// Never called: width_ is 16 only where sixteen_wide_available().
bool WideBvh::intersect16(const Ray&, Hit&, TraversalCost*) const { return false; }
bool WideBvh::occluded16(const Ray&) const { return false; }
#endif

}  // namespace svetlo
