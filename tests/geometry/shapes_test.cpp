#include "svetlo/geometry/shapes.h"

#include <gtest/gtest.h>

namespace svetlo {
namespace {

struct Probe {
    bool hit;
    float t;
    ShapeSurface surface;
};

Probe probe(const Shape& shape, const Ray& ray, Transform transform = {}) {
    AnalyticShape s = make_analytic_shape(shape, transform, 0);
    Probe p{};
    ShapeHit h;
    p.hit = intersect_shape(s, ray, ray.tmax, h);
    p.t = h.t;
    if (p.hit) p.surface = shape_surface(s, ray, h);
    return p;
}

TEST(Sphere, DepthAndNormalFromOutsideAndInside) {
    Sphere sphere{vec3(1, 2, 3), 2.0f};
    Probe p = probe(sphere, Ray{vec3(1, 2, 10), vec3(0, 0, -1)});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 5.0f, 1e-5f);
    EXPECT_NEAR(p.surface.n.z, 1.0f, 1e-6f);
    Probe inside = probe(sphere, Ray{vec3(1, 2, 3), vec3(0, 1, 0)});
    ASSERT_TRUE(inside.hit);
    EXPECT_NEAR(inside.t, 2.0f, 1e-5f);
    EXPECT_NEAR(inside.surface.n.y, 1.0f, 1e-6f);  // outward even from inside
    // An oblique ray: distance from the centre to the ray is 1, so half-chord sqrt(3).
    Probe oblique = probe(sphere, Ray{vec3(2, 2, 10), vec3(0, 0, -1)});
    EXPECT_NEAR(oblique.t, 7.0f - std::sqrt(3.0f), 1e-5f);
    EXPECT_FALSE(probe(sphere, Ray{vec3(3.01f, 2, 10), vec3(0, 0, -1)}).hit);
}

TEST(Sphere, FarAwayHitIsPrecise) {
    // The cancellation-free discriminant keeps a tiny sphere far away exact.
    Probe p = probe(Sphere{vec3(0, 0, -1e4f), 0.01f}, Ray{vec3(0.0f), vec3(0, 0, -1)});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 1e4f - 0.01f, 1e-3f);
}

TEST(Sphere, UnderNonUniformScaleIsAnEllipsoid) {
    Transform t;
    t.matrix = glm::scale(mat4(1.0f), vec3(2, 1, 1));
    t.is_identity = false;
    Probe p = probe(Sphere{vec3(0.0f), 1.0f}, Ray{vec3(10, 0, 0), vec3(-1, 0, 0)}, t);
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 8.0f, 1e-5f);
    EXPECT_NEAR(p.surface.p.x, 2.0f, 1e-5f);
    // The normal of x^2/4 + y^2 = 1 at (sqrt2, 1/sqrt2) is along (x/4, y) = (sqrt2/4, 1/sqrt2).
    float s2 = std::sqrt(2.0f);
    Probe q = probe(Sphere{vec3(0.0f), 1.0f}, Ray{vec3(s2, 10, 0), vec3(0, -1, 0)}, t);
    ASSERT_TRUE(q.hit);
    vec3 expected = glm::normalize(vec3(s2 / 4.0f, 1.0f / s2, 0.0f));
    EXPECT_NEAR(glm::dot(q.surface.n, expected), 1.0f, 1e-5f);
}

TEST(Box, EntryExitAndFaceNormals) {
    Box box{vec3(-1, -2, -3), vec3(1, 2, 3)};
    Probe p = probe(box, Ray{vec3(0, 0, 10), vec3(0, 0, -1)});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 7.0f, 1e-6f);
    EXPECT_EQ(p.surface.n, vec3(0, 0, 1));
    Probe inside = probe(box, Ray{vec3(0.0f), vec3(-1, 0, 0)});
    EXPECT_NEAR(inside.t, 1.0f, 1e-6f);
    EXPECT_EQ(inside.surface.n, vec3(-1, 0, 0));
    // Rotated 90 degrees about z: the x extent becomes 2.
    Transform t;
    t.matrix = glm::rotate(mat4(1.0f), kPi / 2.0f, vec3(0, 0, 1));
    t.is_identity = false;
    Probe rotated = probe(box, Ray{vec3(10, 0, 0), vec3(-1, 0, 0)}, t);
    EXPECT_NEAR(rotated.t, 8.0f, 1e-5f);
    EXPECT_NEAR(rotated.surface.n.x, 1.0f, 1e-5f);
}

TEST(Cylinder, SideAndCaps) {
    Cylinder c{vec3(0, 1, 0), vec3(0, 2, 0), 0.5f};
    Probe side = probe(c, Ray{vec3(5, 2, 0), vec3(-1, 0, 0)});
    ASSERT_TRUE(side.hit);
    EXPECT_NEAR(side.t, 4.5f, 1e-5f);
    EXPECT_NEAR(side.surface.n.x, 1.0f, 1e-6f);
    Probe top = probe(c, Ray{vec3(0.2f, 10, 0), vec3(0, -1, 0)});
    EXPECT_NEAR(top.t, 7.0f, 1e-5f);
    EXPECT_NEAR(top.surface.n.y, 1.0f, 1e-6f);
    Probe bottom = probe(c, Ray{vec3(0.2f, -10, 0), vec3(0, 1, 0)});
    EXPECT_NEAR(bottom.t, 11.0f, 1e-5f);
    EXPECT_NEAR(bottom.surface.n.y, -1.0f, 1e-6f);
    EXPECT_FALSE(probe(c, Ray{vec3(5, 3.1f, 0), vec3(-1, 0, 0)}).hit);  // above the top
}

TEST(Cone, SideAndBase) {
    // Radius 1 at y = 0, apex at y = 2: radius at height y is 1 - y/2.
    Cone c{vec3(0.0f), vec3(0, 2, 0), 1.0f};
    Probe side = probe(c, Ray{vec3(5, 1, 0), vec3(-1, 0, 0)});
    ASSERT_TRUE(side.hit);
    EXPECT_NEAR(side.t, 4.5f, 1e-5f);
    // Normal of x^2 + z^2 = (1 - y/2)^2: along (x, (1 - y/2)/2, 0) = (0.5, 0.25, 0).
    EXPECT_NEAR(glm::dot(side.surface.n, glm::normalize(vec3(0.5f, 0.25f, 0.0f))), 1.0f, 1e-5f);
    Probe base = probe(c, Ray{vec3(0.3f, -4, 0), vec3(0, 1, 0)});
    EXPECT_NEAR(base.t, 4.0f, 1e-5f);
    EXPECT_NEAR(base.surface.n.y, -1.0f, 1e-6f);
    Probe apex = probe(c, Ray{vec3(0, 5, 0), vec3(0, -1, 0)});
    EXPECT_NEAR(apex.t, 3.0f, 1e-4f);
    EXPECT_FALSE(probe(c, Ray{vec3(5, 2.5f, 0), vec3(-1, 0, 0)}).hit);  // the other nappe
}

TEST(Quad, BarycentricBoundsAndUv) {
    Quad q{vec3(0.0f), vec3(2, 0, 0), vec3(0, 0, 1)};
    Probe p = probe(q, Ray{vec3(1.5f, 3, 0.25f), vec3(0, -1, 0)});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 3.0f, 1e-6f);
    EXPECT_NEAR(p.surface.uv.x, 0.75f, 1e-6f);
    EXPECT_NEAR(p.surface.uv.y, 0.25f, 1e-6f);
    EXPECT_EQ(p.surface.n, vec3(0, -1, 0));  // edge_u x edge_v
    EXPECT_FALSE(probe(q, Ray{vec3(2.1f, 3, 0.25f), vec3(0, -1, 0)}).hit);
}

TEST(Plane, InfiniteAndOneSidedNormal) {
    Probe p =
        probe(Plane{vec3(0, -1, 0), vec3(0, 1, 0)}, Ray{vec3(1e3f, 5, -1e3f), vec3(0, -1, 0)});
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 6.0f, 1e-4f);
    EXPECT_FALSE(probe(Plane{vec3(0, -1, 0), vec3(0, 1, 0)}, Ray{vec3(0), vec3(1, 0, 0)}).hit);
}

TEST(Area, ClosedForms) {
    auto area = [](const Shape& s) { return shape_area(make_analytic_shape(s, Transform{}, 0)); };
    EXPECT_NEAR(area(Sphere{vec3(0.0f), 2.0f}), 16.0f * kPi, 1e-4f);
    EXPECT_NEAR(area(Box{vec3(0.0f), vec3(1, 2, 3)}), 22.0f, 1e-5f);
    EXPECT_NEAR(area(Cylinder{vec3(0.0f), vec3(0, 2, 0), 1.0f}), 6.0f * kPi, 1e-4f);
    EXPECT_NEAR(area(Cone{vec3(0.0f), vec3(0, 4, 0), 3.0f}), kPi * 3 * 5 + kPi * 9, 1e-4f);
}

}  // namespace
}  // namespace svetlo
