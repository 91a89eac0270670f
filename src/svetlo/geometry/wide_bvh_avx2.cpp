// The wide BVH's eight-wide traversal (AVX2): WideBvh uses it only where the processor has
// AVX2. The target is set by pragma around this file's own code, after the headers, so that
// no inline function of a header (GLM, the standard library) is emitted with AVX2
// instructions the linker could pick for the rest of the program (as raster/simd_shading).
// No FMA: the box test rounds as the four-wide one does, lane for lane.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "svetlo/geometry/box_tree.h"
#include "svetlo/geometry/ray_box.h"
#include "svetlo/geometry/triangle.h"
#include "svetlo/geometry/wide_bvh.h"
#include "svetlo/geometry/wide_bvh_reference.h"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace svetlo {

namespace {

#include "svetlo/geometry/wide_bvh_packets.inc"
#include "svetlo/geometry/wide_bvh_traversal.inc"

/// A ray against the eight boxes of a node. Its twin: wide::ScalarBoxes<8>
/// (wide_bvh_reference.h).
struct RayBoxes8 {
    static constexpr int kWidth = 8;
    __m256 o[3], inv[3];
    int near[3], far[3];  // box rows of the near and far planes per axis

    explicit RayBoxes8(const Ray& ray) {
        vec3 inv_d = safe_inverse(ray.d);
        for (int a = 0; a < 3; ++a) {
            o[a] = _mm256_set1_ps(ray.o[a]);
            inv[a] = _mm256_set1_ps(inv_d[a]);
            near[a] = inv_d[a] >= 0.0f ? a : a + 3;
            far[a] = inv_d[a] >= 0.0f ? a + 3 : a;
        }
    }

    int test(const WideBvhNode<8>& n, float tmax, float* t_enter) const {
        __m256 tn0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.box[near[0]]), o[0]), inv[0]);
        __m256 tn1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.box[near[1]]), o[1]), inv[1]);
        __m256 tn2 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.box[near[2]]), o[2]), inv[2]);
        __m256 tf0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.box[far[0]]), o[0]), inv[0]);
        __m256 tf1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.box[far[1]]), o[1]), inv[1]);
        __m256 tf2 = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.box[far[2]]), o[2]), inv[2]);
        __m256 enter =
            _mm256_max_ps(_mm256_max_ps(tn0, tn1), _mm256_max_ps(tn2, _mm256_setzero_ps()));
        __m256 exit =
            _mm256_min_ps(_mm256_min_ps(tf0, tf1), _mm256_min_ps(tf2, _mm256_set1_ps(tmax)));
        exit = _mm256_mul_ps(exit, _mm256_set1_ps(kSlabRobust));
        _mm256_store_ps(t_enter, enter);
        return _mm256_movemask_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OS));
    }
};

}  // namespace

int wide::boxes_avx2(const Ray& ray, const WideBvhNode<8>& node, float tmax, float* t_enter) {
    return RayBoxes8(ray).test(node, tmax, t_enter);
}

// (The leaves tested inline: leaf_closest and leaf_any, as leaf_intersect and leaf_occluded.)
bool WideBvh::intersect8(const Ray& ray, Hit& hit, TraversalCost* cost) const {
    const RayPrecomputed pre(ray);
    const SsePackets test(ray, pre);
    auto leaf_test = [&](uint32_t leaf) {
        return leaf_closest(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test, hit);
    };
    if (!cost) return traverse_closest<RayBoxes8>(nodes8_.data(), ray, hit, leaf_test);
    return traverse_closest<RayBoxes8>(
        nodes8_.data(), ray, hit,
        [&](uint32_t leaf) {
            cost->primitives += leaf_lanes(leaf);
            return leaf_test(leaf);
        },
        NodeCount{&cost->nodes});
}

bool WideBvh::occluded8(const Ray& ray) const {
    const RayPrecomputed pre(ray);
    const SsePackets test(ray, pre);
    return traverse_any<RayBoxes8>(nodes8_.data(), ray, [&](uint32_t leaf) {
        return leaf_any(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test);
    });
}

bool WideBvh::occluded8_if(const Ray& ray, HitFilter counts) const {
    const RayPrecomputed pre(ray);
    const SsePackets test(ray, pre);
    const auto counted = [&](const Hit& hit) { return counts(ray, hit); };
    return traverse_any<RayBoxes8>(nodes8_.data(), ray, [&](uint32_t leaf) {
        return leaf_any_if(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test,
                           counted);
    });
}

uint64_t WideBvh::occluded_toward8(vec3 end, const Ray* rays, size_t count,
                                   const PrimitiveRange* skip) const {
    return occluded_packet<8, SsePackets>(nodes8_.data(), leaves_.data(), packets_.data(),
                                          shapes_.data(), geometry_, end, rays, count, skip,
                                          [&](int m) { return occluded8(rays[m]); });
}

bool wide::boxes_closest8(const WideBvhNode<8>* nodes, const Ray& ray, Hit& hit, BoxLeafTest leaf,
                          uint32_t* visited) {
    const auto test = [&](uint32_t box) { return leaf.test(leaf.context, box, hit); };
    if (visited) return traverse_closest<RayBoxes8>(nodes, ray, hit, test, NodeCount{visited});
    return traverse_closest<RayBoxes8>(nodes, ray, hit, test);
}

bool wide::boxes_any8(const WideBvhNode<8>* nodes, const Ray& ray, BoxLeafTest leaf) {
    Hit unread;
    return traverse_any<RayBoxes8>(
        nodes, ray, [&](uint32_t box) { return leaf.test(leaf.context, box, unread); });
}

}  // namespace svetlo

#pragma GCC pop_options
