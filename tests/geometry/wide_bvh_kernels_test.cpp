// The wide BVH's kernels against their scalar twins (wide_bvh_reference.h): the same rays and
// nodes, the same masks and entry distances bit for bit; the same packets, the same hits.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "svetlo/core/rng.h"
#include "svetlo/geometry/avx2.h"
#include "svetlo/geometry/wide_bvh_reference.h"

namespace svetlo {
namespace {

vec3 random_point(Rng& rng, float scale) {
    return scale * vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
}

/// A ray from around the boxes toward them; some directions have a zero component (the
/// slab test's infinite inverse) and some rays start inside a box.
Ray random_ray(Rng& rng) {
    Ray ray;
    ray.o = random_point(rng, 6.0f);
    ray.d = random_point(rng, 2.0f) - ray.o;
    if (rng.next_float() < 0.2f) ray.d[static_cast<int>(rng.next_float() * 3.0f) % 3] = 0.0f;
    ray.tmax = rng.next_float() < 0.3f ? 2.0f * rng.next_float() : kInfinity;
    return ray;
}

/// A node of W children with random boxes, empty lanes (the build's +inf, -inf) and flat ones.
template <int W>
WideBvhNode<W> random_node(Rng& rng) {
    WideBvhNode<W> node;
    for (int k = 0; k < W; ++k) {
        const vec3 a = random_point(rng, 4.0f), b = random_point(rng, 4.0f);
        vec3 lo = glm::min(a, b), hi = glm::max(a, b);
        if (rng.next_float() < 0.1f) hi.y = lo.y;
        const bool empty = rng.next_float() < 0.15f;
        for (int c = 0; c < 3; ++c) {
            node.box[c][k] = empty ? kInfinity : lo[c];
            node.box[c + 3][k] = empty ? -kInfinity : hi[c];
        }
        node.child[k] = static_cast<uint32_t>(k);
    }
    return node;
}

template <int W, class Fast>
void expect_same_boxes(Fast fast) {
    Rng rng(7, W);
    for (int trial = 0; trial < 20000; ++trial) {
        const Ray ray = random_ray(rng);
        const WideBvhNode<W> node = random_node<W>(rng);
        alignas(32) float t_plain[W], t_fast[W];
        const int plain = wide::ScalarBoxes<W>(ray).test(node, ray.tmax, t_plain);
        const int simd = fast(ray, node, ray.tmax, t_fast);
        ASSERT_EQ(plain, simd) << "trial " << trial;
        ASSERT_EQ(std::memcmp(t_plain, t_fast, sizeof t_plain), 0) << "trial " << trial;
    }
}

TEST(WideBvhKernels, ScalarBoxesAgreeWithTheSlabTest) {
    // The twin against ray_box (ray_box.h), the one-box statement, child by child. An empty
    // child (min +inf, max -inf) is missed by the near/far planes' order, where ray_box,
    // which sorts the planes, would turn it into the whole space: it is checked apart.
    Rng rng(3, 3);
    int hits = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        const Ray ray = random_ray(rng);
        const WideBvhNode<4> node = random_node<4>(rng);
        float t[4];
        const int mask = wide::ScalarBoxes<4>(ray).test(node, ray.tmax, t);
        for (int k = 0; k < 4; ++k) {
            const vec3 lo(node.box[0][k], node.box[1][k], node.box[2][k]);
            const vec3 hi(node.box[3][k], node.box[4][k], node.box[5][k]);
            if (lo.x == kInfinity) {
                ASSERT_EQ((mask >> k) & 1, 0) << "trial " << trial << ", empty child " << k;
                continue;
            }
            float t0, t1;
            const bool hit = ray_box(lo, hi, ray.o, safe_inverse(ray.d), ray.tmax, t0, t1);
            ASSERT_EQ(hit, ((mask >> k) & 1) != 0) << "trial " << trial << ", child " << k;
            if (hit) {
                ASSERT_EQ(t0, t[k]);
            }
            hits += hit;
        }
    }
    EXPECT_GT(hits, 2000);  // the rays meet boxes often enough for the test to mean something
}

#if SVETLO_SIMD
TEST(WideBvhKernels, SseBoxTestIsTheScalarOneBitForBit) { expect_same_boxes<4>(wide::boxes_sse); }

TEST(WideBvhKernels, Avx2BoxTestIsTheScalarOneBitForBit) {
    if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this processor";
    expect_same_boxes<8>(wide::boxes_avx2);
}

TEST(WideBvhKernels, Avx512BoxTestIsTheScalarOneBitForBit) {
    if (!avx512_available()) GTEST_SKIP() << "no AVX-512 on this processor";
    expect_same_boxes<16>(wide::boxes_avx512);
}

TEST(WideBvhKernels, SsePacketsHitWhatTheScalarTestHits) {
    Rng rng(11, 4);
    int hits = 0, several = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        // Two packets; neighbours share vertices (edges and corners the rays may cross), a
        // lane may be unused.
        TrianglePacket packets[2];
        const vec3 base = random_point(rng, 2.0f);
        for (int j = 0; j < 2; ++j) {
            for (int k = 0; k < 4; ++k) {
                const bool grid = trial % 2 == 0;
                vec3 v[3] = {base, base + vec3(1, 0, 0), base + vec3(0, 1, 0)};
                if (grid) {
                    v[0] += vec3(0, 0, 0.25f * static_cast<float>(k + 4 * j));  // stacked
                } else {
                    for (vec3& p : v) p = random_point(rng, 3.0f);
                }
                for (int c = 0; c < 9; ++c) packets[j].v[c][k] = v[c / 3][c % 3];
                packets[j].id[k] = rng.next_float() < 0.1f ? ~0u : static_cast<uint32_t>(4 * j + k);
            }
        }
        Ray ray = random_ray(rng);
        if (trial % 4 == 0) {  // along an edge
            ray.o = base + vec3(0.5f, 0.0f, 3.0f);
            ray.d = vec3(0, 0, -1);
        }
        const RayPrecomputed pre(ray);
        Hit plain, fast;
        plain.t = fast.t = ray.tmax;
        const bool a = wide::ScalarPackets(ray, pre).closest(packets, 2, plain);
        const bool b = wide::packets_closest_sse(ray, packets, 2, fast);
        ASSERT_EQ(a, b) << "trial " << trial;
        ASSERT_EQ(plain.prim, fast.prim) << "trial " << trial;
        ASSERT_EQ(std::memcmp(&plain.t, &fast.t, 4), 0) << "trial " << trial;
        ASSERT_EQ(std::memcmp(&plain.u, &fast.u, 4), 0) << "trial " << trial;
        ASSERT_EQ(std::memcmp(&plain.v, &fast.v, 4), 0) << "trial " << trial;
        ASSERT_EQ(wide::ScalarPackets(ray, pre).any(packets, 2),
                  wide::packets_any_sse(ray, packets, 2))
            << "trial " << trial;
        // The filtered any-hit query: every hit before tmax asked of the filter, the same hits
        // (bit for bit) in the same order.
        std::vector<Hit> plain_asked, fast_asked;
        EXPECT_FALSE(wide::ScalarPackets(ray, pre).any_if(packets, 2, [&](const Hit& h) {
            plain_asked.push_back(h);
            return false;
        }));
        wide::packets_hits_sse(ray, packets, 2, fast_asked);
        ASSERT_EQ(plain_asked.size(), fast_asked.size()) << "trial " << trial;
        ASSERT_EQ(plain_asked.empty(), !a) << "trial " << trial;
        for (size_t k = 0; k < plain_asked.size(); ++k) {
            ASSERT_EQ(plain_asked[k].prim, fast_asked[k].prim) << "trial " << trial;
            ASSERT_EQ(std::memcmp(&plain_asked[k].t, &fast_asked[k].t, 4), 0) << "trial " << trial;
            ASSERT_EQ(std::memcmp(&plain_asked[k].u, &fast_asked[k].u, 4), 0) << "trial " << trial;
            ASSERT_EQ(std::memcmp(&plain_asked[k].v, &fast_asked[k].v, 4), 0) << "trial " << trial;
        }
        hits += a;
        several += plain_asked.size() > 1;
    }
    EXPECT_GT(hits, 1000);
    EXPECT_GT(several, 100);  // rays through stacked triangles: each of them asked
}
#endif

}  // namespace
}  // namespace svetlo
