#include "svetlo/geometry/sdf.h"

#include <gtest/gtest.h>

#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

SdfNode sphere(vec3 c, float r) {
    SdfNode n;
    n.op = SdfOp::Sphere;
    n.a = c;
    n.r1 = r;
    return n;
}

SdfNode op(SdfOp o, std::vector<SdfNode> children, float smooth = 0.0f) {
    SdfNode n;
    n.op = o;
    n.children = std::move(children);
    n.smooth = smooth;
    return n;
}

TEST(Implicit, SphereMatchesTheAnalyticSphere) {
    SdfShape sdf(sphere(vec3(0.3f, -0.2f, 0.1f), 1.5f), mat4(1.0f));
    AnalyticShape ref = make_analytic_shape(Sphere{vec3(0.3f, -0.2f, 0.1f), 1.5f}, Transform{}, 0);
    Rng rng(1, 1);
    int hits = 0;
    for (int k = 0; k < 2000; ++k) {
        vec3 o = 5.0f * glm::normalize(vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f,
                                            rng.next_float() - 0.5f));
        vec3 target =
            1.6f * vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
        Ray ray{o, glm::normalize(target - o), kInfinity};
        float t;
        ShapeHit h;
        bool a = sdf.intersect(ray, kInfinity, t), b = intersect_shape(ref, ray, kInfinity, h);
        // Grazing rays within the tolerance of the silhouette may differ.
        vec3 l = ray.o - vec3(0.3f, -0.2f, 0.1f);
        float miss = glm::length(l - glm::dot(l, ray.d) * ray.d) - 1.5f;
        if (std::abs(miss) < 1e-3f) continue;
        ASSERT_EQ(a, b) << k;
        if (!a) continue;
        ++hits;
        EXPECT_NEAR(t, h.t, 2e-6f * h.t) << k;
        vec3 n = sdf.normal(ray.o + t * ray.d);
        vec3 nr = shape_surface(ref, ray, h).n;
        EXPECT_GT(glm::dot(n, nr), 1.0f - 1e-5f) << k;
    }
    EXPECT_GT(hits, 500);
}

TEST(Implicit, SmoothUnionBulgesWhereItMust) {
    // Two spheres of radius 0.6 at x = -0.5 and 0.5; the crease at x = 0 lies at height
    // sqrt(0.36 - 0.25). A blend of radius k fills it: along x = 0, both distances are
    // a = b = sqrt(y^2 + 0.25) - 0.6 and smin = a - k/4, zero where sqrt(y^2 + 0.25) = 0.6 + k/4.
    float k = 0.4f;
    SdfShape sharp(
        op(SdfOp::Union, {sphere(vec3(-0.5f, 0, 0), 0.6f), sphere(vec3(0.5f, 0, 0), 0.6f)}),
        mat4(1.0f));
    SdfShape blend(
        op(SdfOp::Union, {sphere(vec3(-0.5f, 0, 0), 0.6f), sphere(vec3(0.5f, 0, 0), 0.6f)}, k),
        mat4(1.0f));
    Ray down{vec3(0, 2, 0), vec3(0, -1, 0), kInfinity};
    float t_sharp, t_blend;
    ASSERT_TRUE(sharp.intersect(down, kInfinity, t_sharp));
    ASSERT_TRUE(blend.intersect(down, kInfinity, t_blend));
    EXPECT_NEAR(2.0f - t_sharp, std::sqrt(0.36f - 0.25f), 1e-5f);
    float r = 0.6f + 0.25f * k;
    EXPECT_NEAR(2.0f - t_blend, std::sqrt(r * r - 0.25f), 1e-5f);
    // Far from the crease (|a - b| > k) the blend is exactly the union.
    Ray side{vec3(-3, 0, 0), vec3(1, 0, 0), kInfinity};
    ASSERT_TRUE(sharp.intersect(side, kInfinity, t_sharp));
    ASSERT_TRUE(blend.intersect(side, kInfinity, t_blend));
    EXPECT_NEAR(t_sharp, 3.0f - 1.1f, 1e-5f);
    EXPECT_NEAR(t_blend, t_sharp, 1e-5f);
}

TEST(Implicit, PrimitivesAtClosedFormDepths) {
    float t;
    SdfNode torus;
    torus.op = SdfOp::Torus;
    torus.r1 = 1.0f;
    torus.r2 = 0.25f;
    SdfShape tor(torus, mat4(1.0f));
    EXPECT_FALSE(tor.intersect(Ray{vec3(0, 3, 0), vec3(0, -1, 0)}, kInfinity, t));  // the hole
    ASSERT_TRUE(tor.intersect(Ray{vec3(1, 3, 0), vec3(0, -1, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 2.75f, 1e-5f);
    ASSERT_TRUE(tor.intersect(Ray{vec3(-3, 0, 0), vec3(1, 0, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 1.75f, 1e-5f);

    SdfNode rbox;
    rbox.op = SdfOp::RoundedBox;
    rbox.a = vec3(-1);
    rbox.b = vec3(1);
    rbox.r1 = 0.2f;
    SdfShape rb(rbox, mat4(1.0f));
    ASSERT_TRUE(rb.intersect(Ray{vec3(0, 0, 5), vec3(0, 0, -1)}, kInfinity, t));
    EXPECT_NEAR(t, 4.0f, 1e-5f);
    // Along the diagonal of an edge the rounding shows: the corner of the xz edge is cut.
    vec3 d = glm::normalize(vec3(1, 0, 1));
    ASSERT_TRUE(rb.intersect(Ray{vec3(0), d}, kInfinity, t));
    EXPECT_NEAR(t, std::sqrt(2.0f) * 0.8f + 0.2f, 1e-5f);

    SdfNode cyl;
    cyl.op = SdfOp::Cylinder;
    cyl.a = vec3(0, -1, 0);
    cyl.b = vec3(0, 2, 0);
    cyl.r1 = 0.5f;
    SdfShape cy(cyl, mat4(1.0f));
    ASSERT_TRUE(cy.intersect(Ray{vec3(3, 0, 0), vec3(-1, 0, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 2.5f, 1e-5f);
    ASSERT_TRUE(cy.intersect(Ray{vec3(0.2f, 4, 0), vec3(0, -1, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 3.0f, 1e-5f);

    // A sphere cut by a plane (intersection with the half-space below y = 0.5).
    SdfNode plane;
    plane.op = SdfOp::Plane;
    plane.a = vec3(0, 0.5f, 0);
    plane.b = vec3(0, 1, 0);
    SdfShape cut(op(SdfOp::Intersection, {sphere(vec3(0), 1.0f), plane}), mat4(1.0f));
    ASSERT_TRUE(cut.intersect(Ray{vec3(0, 3, 0), vec3(0, -1, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 2.5f, 1e-5f);
    EXPECT_NEAR(cut.normal(vec3(0, 0.5f, 0)).y, 1.0f, 1e-3f);
    EXPECT_TRUE(std::isfinite(cut.bounds().max.y));

    // Difference: a sphere minus a smaller one: a ray from inside the cavity meets its wall.
    SdfShape shell(op(SdfOp::Difference, {sphere(vec3(0), 1.0f), sphere(vec3(0), 0.5f)}),
                   mat4(1.0f));
    ASSERT_TRUE(shell.intersect(Ray{vec3(0), vec3(1, 0, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 0.5f, 1e-5f);
    EXPECT_NEAR(shell.normal(vec3(0.5f, 0, 0)).x, -1.0f, 1e-3f);
}

TEST(Implicit, NonUniformScaleKeepsTheDistanceBound) {
    // A unit sphere stretched 3x along x: an ellipsoid; sphere tracing must not overshoot.
    SdfNode s = sphere(vec3(0), 1.0f);
    SdfShape e(s, glm::scale(mat4(1.0f), vec3(3, 1, 1)));
    float t;
    ASSERT_TRUE(e.intersect(Ray{vec3(-10, 0, 0), vec3(1, 0, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 7.0f, 1e-5f);
    ASSERT_TRUE(e.intersect(Ray{vec3(0, -10, 0), vec3(0, 1, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 9.0f, 1e-5f);
    // Oblique: the ellipsoid x^2/9 + y^2 = 1 along y = 0.5 meets x = -3 sqrt(0.75).
    ASSERT_TRUE(e.intersect(Ray{vec3(-10, 0.5f, 0), vec3(1, 0, 0)}, kInfinity, t));
    EXPECT_NEAR(t, 10.0f - 3.0f * std::sqrt(0.75f), 1e-4f);
    // The bound holds: |f| <= true distance, sampled on a line through the ellipsoid.
    for (float x = -5.0f; x <= 5.0f; x += 0.25f) {
        float f = e.eval(vec3(x, 0.3f, 0.2f));
        EXPECT_LE(std::abs(f), std::abs(std::abs(x) - 3.0f * std::sqrt(1.0f - 0.13f)) + 1.0f) << x;
    }
}

TEST(Implicit, SecondaryRaysLeaveAndCrossTheSurface) {
    SdfShape s(sphere(vec3(0), 1.0f), mat4(1.0f));
    Rng rng(2, 2);
    for (int k = 0; k < 200; ++k) {
        // One draw per statement: the order of a call's arguments is the compiler's (GCC
        // draws them in one order on x86-64 and the other on ARM64).
        const float ox = 4.0f * (rng.next_float() - 0.5f);
        const float oy = 4.0f * (rng.next_float() - 0.5f);
        const vec3 o(ox, oy, 5.0f);
        const float jitter = 0.3f * rng.next_float();
        Ray ray{o, glm::normalize(vec3(0.0f, 0.0f, 0.0f) - o + vec3(jitter, 0, 0)), kInfinity};
        float t;
        if (!s.intersect(ray, kInfinity, t)) continue;
        vec3 p = ray.o + t * ray.d;
        vec3 n = s.normal(p);
        // Reflected: leaves a convex surface, never meets it again.
        vec3 r = glm::reflect(ray.d, n);
        float t2;
        EXPECT_FALSE(s.intersect(Ray{offset_ray_origin(p, n, r), r}, kInfinity, t2)) << k;
        // Straight on through: the exit is the chord's length away.
        Ray through{offset_ray_origin(p, n, ray.d), ray.d};
        ASSERT_TRUE(s.intersect(through, kInfinity, t2)) << k;
        float chord = 2.0f * std::abs(glm::dot(n, ray.d));
        EXPECT_NEAR(t2, chord, 1e-4f) << k;
    }
}

TEST(Implicit, ARayStartingJustInsideFindsItsExit) {
    // A ray through a sphere, restarted just inside where it entered (the Whitted engine's
    // refracted ray): the exit is the chord's length away. Found under ARM64, whose argument
    // evaluation order drew the other test's rays in another order.
    SdfShape s(sphere(vec3(0), 1.0f), mat4(1.0f));
    const Ray ray{vec3(1.77070117f, -0.00979399681f, 5.0f),
                  vec3(-0.282843024f, 0.00187881046f, -0.959164381f), kInfinity};
    float t;
    ASSERT_TRUE(s.intersect(ray, kInfinity, t));
    const vec3 p = ray.o + t * ray.d, n = s.normal(p);
    const Ray through{offset_ray_origin(p, n, ray.d), ray.d};
    float t2;
    ASSERT_TRUE(s.intersect(through, kInfinity, t2));
    EXPECT_NEAR(t2, 2.0f * std::abs(glm::dot(n, ray.d)), 1e-4f);
}

}  // namespace
}  // namespace svetlo
