// Each of the rasterizer's SIMD kernels against its scalar twin (rasterize_kernels.h,
// docs/kernels.md), one call at a time on the same random inputs: the same bits out. A scalar
// build (SVETLO_SIMD=OFF) has no SSE forms; there the twins are the kernels, and these tests
// are skipped with a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/rasterize_kernels.h"
#include "svetlo/raster/shadow_lookup.h"
#include "svetlo/raster/shadow_map_filters.h"

namespace svetlo::raster {
namespace {

#if SVETLO_SIMD

/// Buffers for one kTile x kTile tile, the depths random in [0, 1) (so that the depth test
/// passes at some samples and fails at others), the ids and barycentrics random too.
TileBuffers random_buffers(std::mt19937& rng) {
    TileBuffers buf;
    const size_t samples = static_cast<size_t>(kTile) * kTile;
    buf.reset(samples, samples, false, false);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (size_t i = 0; i < buf.depth.size(); ++i) {
        buf.depth[i] = u(rng);
        buf.tri[i] = static_cast<uint32_t>(rng());
        buf.l1[i] = u(rng);
        buf.l2[i] = u(rng);
    }
    return buf;
}

/// Whether two tiles' buffers hold the same bits (a NaN equals itself here).
void expect_same(const TileBuffers& a, const TileBuffers& b, const std::string& what) {
    auto same = [](const auto& x, const auto& y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof x[0]) == 0;
    };
    EXPECT_TRUE(same(a.depth, b.depth)) << what << ": depth";
    EXPECT_TRUE(same(a.tri, b.tri)) << what << ": ids";
    EXPECT_TRUE(same(a.l1, b.l1)) << what << ": l1";
    EXPECT_TRUE(same(a.l2, b.l2)) << what << ": l2";
}

TEST(RasterKernelTwins, RasterizeSmallWritesTheTwinsBits) {
    // Random small triangles (vertices within kSmall pixels of the span's first sample, in
    // 1/256 pixel), each over a random span of the tile, with and without the depth test and
    // the items: the same depths, ids and barycentrics as the twin, and some samples written.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int32_t> coord(-kSmall * kSubpixel / 2, kSmall * kSubpixel);
    std::uniform_int_distribution<int> corner(0, kTile - kSmall - 1), side(1, kSmall);
    std::uniform_real_distribution<float> depth(0.0f, 1.0f);
    int drew = 0;
    const int triangles = 600;
    for (int n = 0; n < triangles; ++n) {
        int32_t rx[3], ry[3];
        for (int k = 0; k < 3; ++k) {
            rx[k] = coord(rng);
            ry[k] = coord(rng);
        }
        // Wound so that the area is positive (small_edges): else swap two vertices.
        const int64_t area = static_cast<int64_t>(rx[1] - rx[0]) * (ry[2] - ry[0]) -
                             static_cast<int64_t>(rx[2] - rx[0]) * (ry[1] - ry[0]);
        if (area == 0) continue;
        if (area < 0) {
            std::swap(rx[1], rx[2]);
            std::swap(ry[1], ry[2]);
        }
        const float z[3] = {depth(rng), depth(rng), depth(rng)};
        const float inv_area = 1.0f / static_cast<float>(std::llabs(area));
        const SmallEdges e = small_edges(rx, ry);
        const DepthPlane p = depth_plane(rx, ry, z, inv_area);
        const int xs = corner(rng), ys = corner(rng);
        const PixelSpan span{xs, xs + side(rng), ys, ys + side(rng)};
        const Tile tile{0, 0, kTile, kTile};
        const float z_origin = depth_at(p, -rx[0], -ry[0]);
        const bool depth_test = n % 3 != 0;
        const uint32_t id = static_cast<uint32_t>(n);
        const TileBuffers before = random_buffers(rng);
        TileBuffers a = before, b = before;
        if (n % 2 == 0) {
            twin::rasterize_small<true>(e, z_origin, p, span, tile, depth_test, a, id, inv_area);
            sse::rasterize_small<true>(e, z_origin, p, span, tile, depth_test, b, id, inv_area);
        } else {
            twin::rasterize_small<false>(e, z_origin, p, span, tile, depth_test, a);
            sse::rasterize_small<false>(e, z_origin, p, span, tile, depth_test, b);
        }
        expect_same(a, b, "triangle " + std::to_string(n));
        drew += a.depth != before.depth;
    }
    EXPECT_GT(drew, triangles / 4) << "too few triangles wrote a sample to test anything";
}

TEST(RasterKernelTwins, DepthTestFourWritesTheTwinsBits) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), slope(-0.05f, 0.05f);
    std::uniform_int_distribution<size_t> at(0, static_cast<size_t>(kTile) * kTile - 4);
    int wrote = 0;
    for (int n = 0; n < 2000; ++n) {
        const TileBuffers before = random_buffers(rng);
        TileBuffers a = before, b = before;
        const float z = u(rng), dz = slope(rng);
        const size_t i = at(rng);
        const bool depth_test = n % 4 != 0;
        const bool wa = twin::depth_test_four(z, dz, i, 42, depth_test, a);
        const bool wb = sse::depth_test_four(z, dz, i, 42, depth_test, b);
        EXPECT_EQ(wa, wb) << n;
        expect_same(a, b, "call " + std::to_string(n));
        wrote += wa;
    }
    EXPECT_GT(wrote, 500);
    EXPECT_LT(wrote, 2000) << "every call wrote: the depth test was never seen to fail";
}

TEST(RasterKernelTwins, DeepestOfIsTheTwinsMaximum) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    for (int n = 0; n < 2000; ++n) {
        std::vector<float> row(static_cast<size_t>(n % 67));
        for (float& v : row) v = u(rng);
        const float start = n % 5 == 0 ? 1000.0f : u(rng);
        EXPECT_EQ(twin::deepest_of(row.data(), row.size(), start),
                  sse::deepest_of(row.data(), row.size(), start))
            << n;
    }
}

TEST(RasterKernelTwins, DepthRangeIsTheTwinsRange) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    for (int n = 0; n < 2000; ++n) {
        std::vector<float> z(static_cast<size_t>(n % 37));
        for (float& v : z) v = u(rng);
        float near_a = n % 7 == 0 ? -1.0f : u(rng), far_a = near_a + u(rng);
        float near_b = near_a, far_b = far_a;
        twin::depth_range(z.data(), z.size(), near_a, far_a);
        sse::depth_range(z.data(), z.size(), near_b, far_b);
        EXPECT_EQ(near_a, near_b) << n;
        EXPECT_EQ(far_a, far_b) << n;
    }
}

TEST(RasterKernelTwins, ShadowLookup4IsTheTwinsLookup) {
    // Random receivers (points and normals) around a light's map, perspective and
    // orthographic, with the normal offset and slope bias on: the same pixel positions,
    // distances, biases and on-map flags, lane by lane, whichever lane a sample sits in.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    ShadowMapSettings settings;
    settings.normal_offset = 1.5f;
    settings.slope_bias = 2.0f;
    const Bounds3 bounds(vec3(-3.0f), vec3(3.0f));
    for (const Camera::Type type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        Camera light;
        light.type = type;
        light.position = vec3(1.0f, 6.0f, 2.0f);
        light.look_at = vec3(0.0f);
        light.fov_deg = 70.0f;
        light.height = 8.0f;
        DepthMap m;
        m.res = 256;
        m.cam = camera_matrices(light, m.res, m.res, bounds);
        m.view_projection = m.cam.view_projection();
        m.texel = type == Camera::Type::Orthographic ? light.height / m.res
                                                     : 2.0f * std::tan(0.35f) / m.res;
        ShadowCaster c;
        c.kind = type == Camera::Type::Orthographic ? ShadowCaster::Kind::Directional
                                                    : ShadowCaster::Kind::Spot;
        c.position = light.position;
        c.direction = glm::normalize(light.look_at - light.position);
        int on_map = 0;
        for (int n = 0; n < 500; ++n) {
            ShadowSample samples[4];
            const ShadowSample* s[4];
            for (int L = 0; L < 4; ++L) {
                samples[L].p = vec3(u(rng), u(rng), u(rng));
                samples[L].n =
                    glm::normalize(vec3(u(rng), u(rng), u(rng)) + vec3(0.0f, 0.1f, 0.0f));
                s[L] = &samples[L];
            }
            ShadowLookup four[4];
            sse::shadow_lookup4(settings, c, m, s, four);
            for (int L = 0; L < 4; ++L) {
                const ShadowLookup one = twin::shadow_lookup(settings, c, m, samples[L]);
                EXPECT_EQ(one.x, four[L].x) << n << " lane " << L;
                EXPECT_EQ(one.y, four[L].y) << n << " lane " << L;
                EXPECT_EQ(one.receiver, four[L].receiver) << n << " lane " << L;
                EXPECT_EQ(one.slope, four[L].slope) << n << " lane " << L;
                EXPECT_EQ(one.on_map, four[L].on_map) << n << " lane " << L;
                on_map += one.on_map;
            }
        }
        EXPECT_GT(on_map, 200) << "too few samples fell on the map";
        EXPECT_LT(on_map, 2000) << "every sample fell on the map: the edges went untested";
    }
}

TEST(RasterKernelTwins, PcfBlockIsTheTwinsSumInAnotherOrder) {
    // Random maps of distances, kernels of 2 and 3 texels (the SSE form's), random fractions
    // and limits: the same lit weight within float rounding of a sum of at most 16 terms.
    std::mt19937 rng(19);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int res = 8;
    std::vector<float> map(static_cast<size_t>(res) * res);
    double spread = 0.0;
    for (int k = 0; k < 5000; ++k) {
        for (float& v : map) v = u(rng);
        const int n = 2 + k % 2;
        const float fx = u(rng), fy = u(rng), limit = u(rng);
        const float* d = map.data() + (k % 3) * res + k % 4;  // the block fits the map
        const float one = twin::pcf_block(d, res, n, fx, fy, limit);
        const float four = sse::pcf_block(d, res, n, fx, fy, limit);
        EXPECT_NEAR(one, four, 1e-5f) << k;
        spread += one;
    }
    EXPECT_GT(spread, 1000.0) << "the blocks were never lit: nothing was compared";
}

#endif  // (SVETLO_SIMD=OFF: the twins are the kernels, and there is nothing to compare)

}  // namespace
}  // namespace svetlo::raster
