// The wide BVH's sixteen-wide traversal (AVX-512 F): WideBvh uses it only when asked for
// sixteen lanes (`bvh16`) and the processor has AVX-512. As wide_bvh_avx2.cpp, the target is
// set by pragma around this file's own code, after the headers. No FMA: the box test rounds
// as the four- and eight-wide ones do, lane for lane.
#include <immintrin.h>

#include <algorithm>
#include <cstring>
#include <optional>

#include "svetlo/geometry/ray_box.h"
#include "svetlo/geometry/triangle.h"
#include "svetlo/geometry/wide_bvh.h"
#include "svetlo/geometry/wide_bvh_reference.h"

#pragma GCC push_options
#pragma GCC target("avx512f")
// GCC 12's AVX-512 intrinsics start their results from _mm512_undefined_ps(), which it then
// reports as (maybe) uninitialized (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

namespace svetlo {

namespace {

#include "svetlo/geometry/wide_bvh_packets.inc"
#include "svetlo/geometry/wide_bvh_traversal.inc"

/// A ray against the sixteen boxes of a node. Its twin: wide::ScalarBoxes<16>
/// (wide_bvh_reference.h).
struct RayBoxes16 {
    static constexpr int kWidth = 16;
    __m512 o[3], inv[3];
    int near[3], far[3];  // box rows of the near and far planes per axis

    explicit RayBoxes16(const Ray& ray) {
        vec3 inv_d = safe_inverse(ray.d);
        for (int a = 0; a < 3; ++a) {
            o[a] = _mm512_set1_ps(ray.o[a]);
            inv[a] = _mm512_set1_ps(inv_d[a]);
            near[a] = inv_d[a] >= 0.0f ? a : a + 3;
            far[a] = inv_d[a] >= 0.0f ? a + 3 : a;
        }
    }

    int test(const WideBvhNode<16>& n, float tmax, float* t_enter) const {
        __m512 tn0 = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(n.box[near[0]]), o[0]), inv[0]);
        __m512 tn1 = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(n.box[near[1]]), o[1]), inv[1]);
        __m512 tn2 = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(n.box[near[2]]), o[2]), inv[2]);
        __m512 tf0 = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(n.box[far[0]]), o[0]), inv[0]);
        __m512 tf1 = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(n.box[far[1]]), o[1]), inv[1]);
        __m512 tf2 = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(n.box[far[2]]), o[2]), inv[2]);
        // vmaxps and vminps return the second operand on a NaN, as SSE's do (lane_max, lane_min).
        __m512 enter =
            _mm512_max_ps(_mm512_max_ps(tn0, tn1), _mm512_max_ps(tn2, _mm512_setzero_ps()));
        __m512 exit =
            _mm512_min_ps(_mm512_min_ps(tf0, tf1), _mm512_min_ps(tf2, _mm512_set1_ps(tmax)));
        exit = _mm512_mul_ps(exit, _mm512_set1_ps(kSlabRobust));
        _mm512_storeu_ps(t_enter, enter);
        return static_cast<int>(_mm512_cmp_ps_mask(enter, exit, _CMP_LE_OS));
    }
};

}  // namespace

int wide::boxes_avx512(const Ray& ray, const WideBvhNode<16>& node, float tmax, float* t_enter) {
    return RayBoxes16(ray).test(node, tmax, t_enter);
}

// (The leaves tested inline: leaf_closest and leaf_any, as in wide_bvh_avx2.cpp.)
bool WideBvh::intersect16(const Ray& ray, Hit& hit, TraversalCost* cost) const {
    const RayPrecomputed pre(ray);
    const SsePackets test(ray, pre);
    auto leaf_test = [&](uint32_t leaf) {
        return leaf_closest(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test, hit);
    };
    if (!cost) return traverse_closest<RayBoxes16>(nodes16_.data(), ray, hit, leaf_test);
    return traverse_closest<RayBoxes16>(
        nodes16_.data(), ray, hit,
        [&](uint32_t leaf) {
            cost->primitives += leaf_lanes(leaf);
            return leaf_test(leaf);
        },
        NodeCount{&cost->nodes});
}

bool WideBvh::occluded16(const Ray& ray) const {
    const RayPrecomputed pre(ray);
    const SsePackets test(ray, pre);
    return traverse_any<RayBoxes16>(nodes16_.data(), ray, [&](uint32_t leaf) {
        return leaf_any(leaves_[leaf], packets_.data(), shapes_.data(), geometry_, test);
    });
}

}  // namespace svetlo

#pragma GCC diagnostic pop
#pragma GCC pop_options
