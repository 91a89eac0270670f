#include "svetlo/geometry/csg.h"

#include <gtest/gtest.h>

#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

Object leaf(Shape s, int material = 0, Transform t = {}) {
    Object o;
    o.shape = std::move(s);
    o.material = material;
    o.transform = t;
    return o;
}

Object node(CsgOp op, std::vector<Object> children, Transform t = {}) {
    Object o;
    o.shape = Csg{op, std::move(children)};
    o.transform = t;
    return o;
}

AnalyticShape make(const Object& root, Transform t = {}) {
    return make_analytic_shape(root.shape, t, 0);
}

struct Probe {
    bool hit = false;
    float t = 0.0f;
    ShapeSurface s{};
};

Probe probe(const AnalyticShape& shape, vec3 o, vec3 d, float tmax = kInfinity) {
    Probe p;
    ShapeHit h;
    Ray ray{o, d, tmax};
    p.hit = intersect_shape(shape, ray, tmax, h);
    if (p.hit) {
        p.t = h.t;
        p.s = shape_surface(shape, ray, h);
    }
    return p;
}

constexpr float kTol = 1e-5f;

TEST(Csg, UnionOfTwoSpheresHasTheOuterDepths) {
    // Unit spheres at x = -0.5 and x = +0.5.
    AnalyticShape s = make(node(CsgOp::Union, {leaf(Sphere{vec3(-0.5f, 0, 0), 1.0f}),
                                               leaf(Sphere{vec3(0.5f, 0, 0), 1.0f})}));
    Probe p = probe(s, vec3(-5, 0, 0), vec3(1, 0, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 3.5f, kTol);
    EXPECT_NEAR(p.s.n.x, -1.0f, kTol);
    // From inside the overlap, the exit is the far side of the second sphere.
    p = probe(s, vec3(0, 0, 0), vec3(1, 0, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 1.5f, kTol);
    EXPECT_NEAR(p.s.n.x, 1.0f, kTol);
    // The inner surfaces (inside the other sphere) are never hit.
    p = probe(s, vec3(0, 0, 5), vec3(0, 0, -1));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 5.0f - std::sqrt(0.75f), kTol);
}

TEST(Csg, IntersectionIsTheLens) {
    AnalyticShape s = make(node(CsgOp::Intersection, {leaf(Sphere{vec3(-0.5f, 0, 0), 1.0f}),
                                                      leaf(Sphere{vec3(0.5f, 0, 0), 1.0f})}));
    Probe p = probe(s, vec3(-5, 0, 0), vec3(1, 0, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 4.5f, kTol);  // enters at x = -0.5: the right sphere's surface
    EXPECT_NEAR(p.s.n.x, -1.0f, kTol);
    EXPECT_FALSE(probe(s, vec3(-1.2f, 5, 0), vec3(0, -1, 0)).hit);  // inside the left only
    p = probe(s, vec3(0, 5, 0), vec3(0, -1, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 5.0f - std::sqrt(0.75f), kTol);
}

TEST(Csg, DifferenceFlipsTheCutterNormals) {
    // A unit cube minus a sphere of radius 0.5 centred on its top face.
    AnalyticShape s = make(
        node(CsgOp::Difference, {leaf(Box{vec3(-1), vec3(1)}), leaf(Sphere{vec3(0, 1, 0), 0.5f})}));
    Probe p = probe(s, vec3(0, 5, 0), vec3(0, -1, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 4.5f, kTol);      // the bottom of the spherical dent, y = 0.5
    EXPECT_NEAR(p.s.n.y, 1.0f, kTol);  // facing out of the solid: the sphere's normal reversed
    p = probe(s, vec3(0.8f, 5, 0), vec3(0, -1, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 4.0f, kTol);  // beside the dent: the cube's top
    EXPECT_NEAR(p.s.n.y, 1.0f, kTol);
    // Slanted: the dent's normal points toward the sphere's centre.
    p = probe(s, vec3(0.3f, 5, 0), vec3(0, -1, 0));
    ASSERT_TRUE(p.hit);
    vec3 q = vec3(0.3f, 5.0f - p.t, 0.0f);
    EXPECT_NEAR(glm::length(q - vec3(0, 1, 0)), 0.5f, kTol);
    vec3 expected = glm::normalize(vec3(0, 1, 0) - q);
    EXPECT_NEAR(glm::dot(p.s.n, expected), 1.0f, 1e-4f);
}

TEST(Csg, CoincidentFacesLeaveNoSkin) {
    // A box minus a box sharing its top face: the top is cut down to y = 0, everywhere.
    AnalyticShape s = make(node(CsgOp::Difference, {leaf(Box{vec3(-1), vec3(1)}),
                                                    leaf(Box{vec3(-2, 0, -2), vec3(2, 1, 2)})}));
    Rng rng(3, 4);
    for (int k = 0; k < 1000; ++k) {
        vec3 o(2.0f * rng.next_float() - 1.0f, 3.0f, 2.0f * rng.next_float() - 1.0f);
        Probe p = probe(s, o, vec3(0, -1, 0));
        ASSERT_TRUE(p.hit);
        EXPECT_EQ(p.t, 3.0f) << k;
    }
    // Two boxes meeting face to face merge: a ray along the seam's normal does not stop there.
    AnalyticShape u = make(
        node(CsgOp::Union, {leaf(Box{vec3(0), vec3(1)}), leaf(Box{vec3(1, 0, 0), vec3(2, 1, 1)})}));
    Probe p = probe(u, vec3(0.5f, 0.5f, 0.5f), vec3(1, 0, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 1.5f, kTol);
}

// A hole drilled by a cylinder exactly as long as the box is thick: its caps lie on the box's
// faces, but their t values come from the cylinder's frame and differ from the box's by
// rounding, leaving slivers of box at the openings. Rays down the hole hit them, and shadow
// rays from the hole's wall toward a light beyond the opening stopped in them: black speckles
// where light reaches the wall (the fuzzer's "acne" on CSG holes). Spheres and boxes as
// cutters were clean: no cap, or the same slab arithmetic on both sides.
TEST(Csg, AFlushCylinderDrillsACleanHole) {
    Transform placed;
    placed.matrix = glm::translate(mat4(1.0f), vec3(-100.0f, -5.0f, 0.0f)) *
                    glm::rotate(mat4(1.0f), 0.48f, glm::normalize(vec3(0.72f, -0.38f, 0.88f))) *
                    glm::scale(mat4(1.0f), vec3(10.0f));
    placed.is_identity = false;
    const float r = 0.4f;
    AnalyticShape s =
        make(node(CsgOp::Difference,
                  {leaf(Box{vec3(-1), vec3(1)}), leaf(Cylinder{vec3(0, 0, -1), vec3(0, 0, 2), r})}),
             placed);
    auto world = [&](vec3 local) { return vec3(placed.matrix * vec4(local, 1.0f)); };
    vec3 light = world(vec3(0.05f, -0.03f, 4.0f));
    Rng rng(7, 8);
    int through = 0, speckles = 0, lit = 0;
    for (int k = 0; k < 4000; ++k) {
        // Down the hole, parallel to its axis, inside its radius: nothing is hit.
        float a = 6.2831853f * rng.next_float(), q = 0.9f * r * std::sqrt(rng.next_float());
        vec3 from = world(vec3(q * std::cos(a), q * std::sin(a), 3.0f));
        vec3 to = world(vec3(q * std::cos(a), q * std::sin(a), -3.0f));
        through += probe(s, from, to - from, 1.0f).hit ? 1 : 0;
        // From the light to the wall, and the shadow ray back: a wall point the light's ray
        // reached is lit.
        float z = 1.9f * rng.next_float() - 0.95f;
        vec3 target = world(vec3(r * std::cos(a), r * std::sin(a), z));
        Probe p = probe(s, light, glm::normalize(target - light));
        if (!p.hit) continue;
        vec3 wi = light - p.s.p;
        Probe back = probe(s, offset_ray_origin(p.s.p, p.s.n, wi), wi, 1.0f);
        ++lit;
        speckles += back.hit ? 1 : 0;
    }
    EXPECT_EQ(through, 0);
    EXPECT_GT(lit, 1000);
    EXPECT_EQ(speckles, 0);
}

TEST(Csg, TheDrilledCubesHoleWallsAreLitWhereALightReachesThem) {
    // The classic drilled cube: a box intersected with a sphere, minus three cylinders longer
    // than the solid (not flush: their caps lie outside it), rotated and moved. A point the
    // light's ray reaches is lit: the shadow ray back from it must reach the light. Each
    // light's rays aim at the holes' walls, from their mouths to the junction of the holes,
    // where the rays meet the walls at every angle down to grazing.
    Transform placed;
    placed.matrix = glm::translate(mat4(1.0f), vec3(-2.1f, 0.7f, -0.3f)) *
                    glm::rotate(mat4(1.0f), glm::radians(30.0f), vec3(0, 1, 0));
    placed.is_identity = false;
    const float r = 0.38f;
    std::vector<Object> cutters;
    for (int axis = 0; axis < 3; ++axis) {
        vec3 base(0.0f), along(0.0f);
        base[axis] = -1.0f;
        along[axis] = 2.0f;
        cutters.push_back(leaf(Cylinder{base, along, r}));
    }
    AnalyticShape s =
        make(node(CsgOp::Difference, {node(CsgOp::Intersection, {leaf(Box{vec3(-0.7f), vec3(0.7f)}),
                                                                 leaf(Sphere{vec3(0.0f), 0.95f})}),
                                      cutters[0], cutters[1], cutters[2]}),
             placed);
    auto world = [&](vec3 local) { return vec3(placed.matrix * vec4(local, 1.0f)); };
    Rng rng(11, 12);
    int lit = 0, speckles = 0;
    for (vec3 light : {vec3(-5, 8, 6), vec3(6, 5, 2)}) {
        for (int k = 0; k < 30000; ++k) {
            // A point of a cylinder's wall, anywhere along the hole.
            const int axis = k % 3;
            const float a = 6.2831853f * rng.next_float(), along = 1.4f * rng.next_float() - 0.7f;
            vec3 local(0.0f);
            local[axis] = along;
            local[(axis + 1) % 3] = r * std::cos(a);
            local[(axis + 2) % 3] = r * std::sin(a);
            Probe p = probe(s, light, glm::normalize(world(local) - light));
            if (!p.hit) continue;
            const vec3 wi = light - p.s.p;
            Probe back = probe(s, offset_ray_origin(p.s.p, p.s.n, wi), wi, 1.0f);
            ++lit;
            if (back.hit) {
                ++speckles;
                ADD_FAILURE() << "blocked at t " << back.t << " (of 1), from " << p.s.p.x << " "
                              << p.s.p.y << " " << p.s.p.z << " toward " << light.x << " "
                              << light.y << " " << light.z;
            }
        }
    }
    EXPECT_GT(lit, 20000);
    EXPECT_EQ(speckles, 0);
}

TEST(Csg, NestedTreesWithTransformsAtEveryLevel) {
    Transform up;
    up.matrix = glm::translate(mat4(1.0f), vec3(0, 2, 0));
    up.is_identity = false;
    Transform twice;
    twice.matrix = glm::scale(mat4(1.0f), vec3(2.0f));
    twice.is_identity = false;
    // (unit sphere minus a cylinder along z of radius 0.25), the whole scaled 2x, then moved up 2.
    Object inner = node(
        CsgOp::Difference,
        {leaf(Sphere{vec3(0), 1.0f}), leaf(Cylinder{vec3(0, 0, -2), vec3(0, 0, 4), 0.25f})}, twice);
    AnalyticShape s = make(node(CsgOp::Union, {inner}), up);
    Probe p = probe(s, vec3(0, 2, 10), vec3(0, 0, -1));  // down the hole: nothing
    EXPECT_FALSE(p.hit);
    p = probe(s, vec3(0, 2.75f, 10), vec3(0, 0, -1));  // beside the hole (0.5 < 0.75 < 2)
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 10.0f - std::sqrt(4.0f - 0.75f * 0.75f), 1e-4f);
    p = probe(s, vec3(0, 2, 0), vec3(0, 1, 0));  // from the hole up: the cylinder wall
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.5f, 1e-5f);
    EXPECT_NEAR(p.s.n.y, -1.0f, 1e-4f);  // facing into the hole
}

TEST(Csg, ConesAndCylindersIntersectAtClosedFormDepths) {
    // A cone (apex at y = 2, base radius 1 at y = 0) intersected with a slab box y < 1.
    AnalyticShape s = make(node(CsgOp::Intersection, {leaf(Cone{vec3(0), vec3(0, 2, 0), 1.0f}),
                                                      leaf(Box{vec3(-5, -1, -5), vec3(5, 1, 5)})}));
    Probe p = probe(s, vec3(0, 5, 0), vec3(0, -1, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 4.0f, kTol);  // the box's top cuts the cone at y = 1
    p = probe(s, vec3(5, 0.5f, 0), vec3(-1, 0, 0));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 5.0f - 0.75f, kTol);  // cone radius at y = 0.5 is 0.75
}

TEST(Csg, ClosedMeshLeaves) {
    // A unit cube as a closed, outward-wound mesh, minus a sphere at its centre of radius 0.25.
    Mesh cube;
    cube.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                      {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    cube.indices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                    3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    AnalyticShape s =
        make(node(CsgOp::Difference, {leaf(cube, 1), leaf(Sphere{vec3(0.5f), 0.25f}, 2)}));
    Probe p = probe(s, vec3(0.5f, 0.5f, 5), vec3(0, 0, -1));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 4.0f, kTol);
    EXPECT_EQ(p.s.material, 1u);
    EXPECT_NEAR(p.s.n.z, 1.0f, kTol);
    // From inside the cavity: the sphere's wall, facing inward, with the sphere's material.
    p = probe(s, vec3(0.5f), vec3(0, 0, 1));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.25f, kTol);
    EXPECT_EQ(p.s.material, 2u);
    EXPECT_NEAR(p.s.n.z, -1.0f, kTol);
    // Inside the solid part of the cube, heading out.
    p = probe(s, vec3(0.5f, 0.5f, 0.9f), vec3(0, 0, 1));
    ASSERT_TRUE(p.hit);
    EXPECT_NEAR(p.t, 0.1f, kTol);
    EXPECT_TRUE(s.csg->contains(vec3(0.1f, 0.5f, 0.5f)));
    EXPECT_FALSE(s.csg->contains(vec3(0.5f)));
    EXPECT_FALSE(s.csg->contains(vec3(1.5f, 0.5f, 0.5f)));
}

TEST(Csg, MaterialPerChildOrInherited) {
    Object a = leaf(Sphere{vec3(-0.5f, 0, 0), 1.0f}, 3);
    Object b = leaf(Sphere{vec3(0.5f, 0, 0), 1.0f}, -1);  // takes the node's
    AnalyticShape s = make_analytic_shape(Csg{CsgOp::Union, {a, b}}, Transform{}, 7);
    EXPECT_EQ(probe(s, vec3(-5, 0, 0), vec3(1, 0, 0)).s.material, 3u);
    EXPECT_EQ(probe(s, vec3(5, 0, 0), vec3(-1, 0, 0)).s.material, 7u);
}

TEST(Csg, SecondaryRaysDoNotHitTheirOwnSurface) {
    AnalyticShape s = make(node(CsgOp::Difference, {leaf(Sphere{vec3(0), 1.0f}),
                                                    leaf(Box{vec3(-2, 0.5f, -2), vec3(2, 2, 2)})}));
    Rng rng(5, 6);
    for (int k = 0; k < 500; ++k) {
        vec3 o(2.0f * rng.next_float() - 1.0f, 3.0f, 2.0f * rng.next_float() - 1.0f);
        Ray ray{o, glm::normalize(vec3(0.1f, -1.0f, 0.2f)), kInfinity};
        Probe p = probe(s, ray.o, ray.d);
        if (!p.hit) continue;
        vec3 n = p.s.n;
        vec3 r = glm::reflect(ray.d, n);
        if (glm::dot(r, n) <= 0.0f) continue;
        Probe back = probe(s, offset_ray_origin(p.s.p, n, r), r);
        // The only surface a reflected ray can meet on this convex-from-outside solid is far.
        if (back.hit) {
            EXPECT_GT(back.t, 1e-3f) << k;
        }
    }
}

}  // namespace
}  // namespace svetlo
