// The wide BVH's kernels in plain C++: the statement of what wide_bvh.cpp (SSE, four lanes)
// and wide_bvh_avx2.cpp (AVX2, eight lanes) compute, and the kernels themselves where svetlo
// is built without SIMD (SVETLO_SIMD=OFF, and on ARM64). Read these first (docs/reading.md).
//
// - ScalarBoxes<W>: a ray against the W child boxes of a node, one slab test per child
//   (Kay and Kajiya 1986; Williams et al. 2005), the same operations in the same order as the
//   SIMD lanes, so the same entry distances and the same mask, bit for bit.
// - ScalarPackets: a leaf's packets of four triangles, one triangle at a time with the
//   watertight test (triangle.h), which the four-lane test copies operation for operation.
//
// tests/geometry/wide_bvh_kernels_test.cpp runs both forms on the same inputs.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/geometry/geometry.h"
#include "svetlo/geometry/ray.h"
#include "svetlo/geometry/ray_box.h"
#include "svetlo/geometry/triangle.h"
#include "svetlo/geometry/wide_bvh.h"

namespace svetlo::wide {

/// The minimum and maximum as the SSE instructions define them: the second operand when the
/// comparison fails (a NaN in either), so that the scalar and SIMD forms agree on every input.
inline float lane_min(float a, float b) { return a < b ? a : b; }
inline float lane_max(float a, float b) { return a > b ? a : b; }

/// A ray against the W boxes of a node: returns the mask of children whose box the ray enters
/// before tmax (bit k for child k) and their entry distances.
template <int W>
struct ScalarBoxes {
    static constexpr int kWidth = W;
    vec3 o, inv;
    int near[3], far[3];  // box rows of the near and far planes per axis

    explicit ScalarBoxes(const Ray& ray) : o(ray.o), inv(safe_inverse(ray.d)) {
        for (int a = 0; a < 3; ++a) {
            near[a] = inv[a] >= 0.0f ? a : a + 3;
            far[a] = inv[a] >= 0.0f ? a + 3 : a;
        }
    }

    int test(const WideBvhNode<W>& n, float tmax, float* t_enter) const {
        int mask = 0;
        for (int k = 0; k < W; ++k) {
            float tn[3], tf[3];  // where the ray crosses the near and far plane of each slab
            for (int a = 0; a < 3; ++a) {
                tn[a] = (n.box[near[a]][k] - o[a]) * inv[a];
                tf[a] = (n.box[far[a]][k] - o[a]) * inv[a];
            }
            const float enter = lane_max(lane_max(tn[0], tn[1]), lane_max(tn[2], 0.0f));
            const float exit =
                lane_min(lane_min(tf[0], tf[1]), lane_min(tf[2], tmax)) * kSlabRobust;
            t_enter[k] = enter;
            if (enter <= exit) mask |= 1 << k;
        }
        return mask;
    }
};

/// A leaf's triangle packets, one triangle at a time (triangle.h).
struct ScalarPackets {
    const Ray& ray;
    const RayPrecomputed& pre;

    ScalarPackets(const Ray& r, const RayPrecomputed& p) : ray(r), pre(p) {}

    static bool lane(const TrianglePacket& p, int k, const Ray& ray, const RayPrecomputed& pre,
                     float tmax, float& t, float& b1, float& b2) {
        const vec3 v0(p.v[0][k], p.v[1][k], p.v[2][k]), v1(p.v[3][k], p.v[4][k], p.v[5][k]),
            v2(p.v[6][k], p.v[7][k], p.v[8][k]);
        return intersect_triangle(ray, pre, v0, v1, v2, tmax, t, b1, b2);
    }

    /// The closest hit among `count` packets, updating hit (t, prim, u, v); ties to the first.
    bool closest(const TrianglePacket* packets, uint32_t count, Hit& hit) const {
        bool found = false;
        for (uint32_t j = 0; j < count; ++j) {
            for (int k = 0; k < 4; ++k) {
                float t, b1, b2;
                if (packets[j].id[k] == ~0u || !lane(packets[j], k, ray, pre, hit.t, t, b1, b2))
                    continue;
                hit.t = t;
                hit.u = b1;
                hit.v = b2;
                hit.prim = packets[j].id[k];
                hit.part = 0;
                hit.sub = 0;
                found = true;
            }
        }
        return found;
    }

    /// Whether any triangle of `count` packets is hit before ray.tmax.
    bool any(const TrianglePacket* packets, uint32_t count) const {
        for (uint32_t j = 0; j < count; ++j) {
            for (int k = 0; k < 4; ++k) {
                float t, b1, b2;
                if (packets[j].id[k] != ~0u && lane(packets[j], k, ray, pre, ray.tmax, t, b1, b2))
                    return true;
            }
        }
        return false;
    }

    /// Whether a triangle of `count` packets is hit before ray.tmax where `counts(hit)` says
    /// the hit (t, prim, u, v) counts (Accel::occluded_if); asked in the packets' order.
    template <class Counts>
    bool any_if(const TrianglePacket* packets, uint32_t count, const Counts& counts) const {
        for (uint32_t j = 0; j < count; ++j) {
            for (int k = 0; k < 4; ++k) {
                Hit hit;
                if (packets[j].id[k] == ~0u ||
                    !lane(packets[j], k, ray, pre, ray.tmax, hit.t, hit.u, hit.v))
                    continue;
                hit.prim = packets[j].id[k];
                if (counts(hit)) return true;
            }
        }
        return false;
    }
};

#if SVETLO_SIMD
// The SIMD forms, for the tests that hold them against the twins above.
int boxes_sse(const Ray& ray, const WideBvhNode<4>& node, float tmax, float* t_enter);
/// Only where avx2_available() (avx2.h).
int boxes_avx2(const Ray& ray, const WideBvhNode<8>& node, float tmax, float* t_enter);
/// The sixteen-wide AVX-512 test (needs avx512_available()); t_enter holds 16 floats.
int boxes_avx512(const Ray& ray, const WideBvhNode<16>& node, float tmax, float* t_enter);
bool packets_closest_sse(const Ray& ray, const TrianglePacket* packets, uint32_t count, Hit& hit);
bool packets_any_sse(const Ray& ray, const TrianglePacket* packets, uint32_t count);
/// SsePackets::any_if with a filter that keeps each hit it is asked about in `asked` and
/// counts none: every hit before ray.tmax, in the order the kernel meets them.
void packets_hits_sse(const Ray& ray, const TrianglePacket* packets, uint32_t count,
                      std::vector<Hit>& asked);
#endif

}  // namespace svetlo::wide
