#include "svetlo/geometry/triangle.h"

#include <gtest/gtest.h>

#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

bool hit(const Ray& r, vec3 a, vec3 b, vec3 c, float* t_out = nullptr) {
    RayPrecomputed pre(r);
    float t, b1, b2;
    bool h = intersect_triangle(r, pre, a, b, c, r.tmax, t, b1, b2);
    if (h && t_out) *t_out = t;
    return h;
}

TEST(Triangle, DepthAndBarycentrics) {
    Ray r{vec3(0.25f, 0.25f, 5.0f), vec3(0, 0, -1)};
    RayPrecomputed pre(r);
    float t, b1, b2;
    ASSERT_TRUE(intersect_triangle(r, pre, vec3(0, 0, 1), vec3(1, 0, 1), vec3(0, 1, 1), kInfinity,
                                   t, b1, b2));
    EXPECT_NEAR(t, 4.0f, 1e-6f);
    EXPECT_NEAR(b1, 0.25f, 1e-6f);
    EXPECT_NEAR(b2, 0.25f, 1e-6f);
    EXPECT_FALSE(hit(Ray{vec3(0.6f, 0.6f, 5.0f), vec3(0, 0, -1)}, vec3(0, 0, 1), vec3(1, 0, 1),
                     vec3(0, 1, 1)));
    // Both windings are hit (culling is the caller's business).
    EXPECT_TRUE(hit(r, vec3(0, 0, 1), vec3(0, 1, 1), vec3(1, 0, 1)));
}

TEST(Triangle, WatertightAcrossSharedEdgesAndVertices) {
    // A fan of triangles around a centre, in a tilted plane; rays aimed exactly at the shared
    // edges and the shared vertex must hit at least one triangle: never fall through a crack.
    const int n = 7;
    vec3 centre(0.3f, -0.2f, 0.1f);
    vec3 u = glm::normalize(vec3(1, 0.3f, 0.2f)),
         v = glm::normalize(glm::cross(vec3(0.1f, 0.2f, 1), u));
    std::vector<vec3> rim;
    for (int k = 0; k < n; ++k) {
        float a = 2.0f * kPi * k / n;
        rim.push_back(centre + std::cos(a) * u + std::sin(a) * v);
    }
    Rng rng(1, 1);
    int rays = 0;
    for (int k = 0; k < n; ++k) {
        for (int s = 0; s <= 50; ++s) {
            // Points on the edge centre -> rim[k], including the centre and the rim vertex.
            vec3 target = glm::mix(centre, rim[k], s / 50.0f);
            vec3 origin = target + 3.0f * glm::normalize(vec3(rng.next_float() - 0.5f,
                                                              rng.next_float() - 0.5f, 1.0f));
            Ray r{origin, target - origin};
            int hits = 0;
            for (int m = 0; m < n; ++m) hits += hit(r, centre, rim[m], rim[(m + 1) % n]);
            if (s < 50) {
                EXPECT_GE(hits, 1) << "edge " << k << " step " << s;
            }
            ++rays;
        }
    }
    EXPECT_EQ(rays, n * 51);
}

TEST(Triangle, RespectsTmax) {
    Ray r{vec3(0.1f, 0.1f, 5.0f), vec3(0, 0, -1), 3.0f};
    EXPECT_FALSE(hit(r, vec3(0, 0, 1), vec3(1, 0, 1), vec3(0, 1, 1)));
    r.tmax = 4.001f;
    EXPECT_TRUE(hit(r, vec3(0, 0, 1), vec3(1, 0, 1), vec3(0, 1, 1)));
}

}  // namespace
}  // namespace svetlo

namespace svetlo {
namespace {

TEST(TriangleNormal, AnyTriangleAFloatHoldsHasAFiniteUnitNormal) {
    // 6e38 wide: the float cross product overflows (inf * 0 = NaN); double precision does not.
    vec3 n = triangle_normal(vec3(-3e38f, 0, 0), vec3(3e38f, 0, 0), vec3(0, 1, 0));
    EXPECT_EQ(n, vec3(0, 0, 1));
    // Ordinary triangles: the same bits as normalising the float cross product.
    vec3 a(0.1f, 0.2f, 0.3f), b(1.7f, -0.4f, 0.9f), c(-0.3f, 1.1f, 0.25f);
    EXPECT_EQ(triangle_normal(a, b, c), glm::normalize(glm::cross(b - a, c - a)));
    // No area: +z.
    EXPECT_EQ(triangle_normal(a, a, c), vec3(0, 0, 1));
}

}  // namespace
}  // namespace svetlo
