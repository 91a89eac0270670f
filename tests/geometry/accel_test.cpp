#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/string_cast.hpp>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/geometry/bvh.h"
#include "svetlo/geometry/grid.h"
#include "svetlo/geometry/octree.h"
#include "svetlo/geometry/wide_bvh.h"

namespace svetlo {
namespace {

/// A random soup of small triangles and shapes (some transformed) in the unit cube.
Geometry random_geometry(int triangles, int shapes, uint64_t seed) {
    Rng rng(seed, 1);
    auto rnd = [&] { return rng.next_float(); };
    Geometry g;
    for (int k = 0; k < triangles; ++k) {
        vec3 c(rnd(), rnd(), rnd());
        for (int v = 0; v < 3; ++v) {
            g.positions.push_back(c + 0.05f * vec3(rnd() - 0.5f, rnd() - 0.5f, rnd() - 0.5f));
            g.indices.push_back(static_cast<uint32_t>(g.positions.size() - 1));
        }
        g.triangle_material.push_back(0);
    }
    for (int k = 0; k < shapes; ++k) {
        vec3 c(rnd(), rnd(), rnd());
        Transform t;
        if (k % 3 == 0) {
            t.matrix =
                glm::rotate(mat4(1.0f), rnd() * 3.0f, glm::normalize(vec3(rnd(), rnd(), 1.0f)));
            t.is_identity = false;
        }
        Shape s;
        switch (k % 4) {
            case 0:
                s = Sphere{c, 0.02f + 0.03f * rnd()};
                break;
            case 1:
                s = Box{c, c + vec3(0.04f)};
                break;
            case 2:
                s = Cylinder{c, vec3(0.0f, 0.05f, 0.01f), 0.02f};
                break;
            default:
                s = Cone{c, vec3(0.01f, 0.05f, 0.0f), 0.03f};
                break;
        }
        g.shapes.push_back(make_analytic_shape(s, t, 0));
    }
    // A few CSG and implicit shapes: their bounds must hold them for every structure.
    for (int k = 0; k < shapes / 20; ++k) {
        vec3 c(rnd(), rnd(), rnd());
        Object body, cut;
        body.shape = Sphere{c, 0.04f};
        body.material = cut.material = 0;
        cut.shape = Box{c, c + vec3(0.05f)};
        g.shapes.push_back(
            make_analytic_shape(Csg{CsgOp::Difference, {body, cut}}, Transform{}, 0));
        SdfNode a, b, blend;
        a.op = b.op = SdfOp::Sphere;
        a.a = c + vec3(0.0f, 0.0f, 0.1f);
        b.a = c + vec3(0.03f, 0.0f, 0.1f);
        a.r1 = b.r1 = 0.02f;
        blend.op = SdfOp::Union;
        blend.smooth = 0.02f;
        blend.children = {a, b};
        g.shapes.push_back(make_analytic_shape(Implicit{blend}, Transform{}, 0));
    }
    return g;
}

/// Every acceleration structure against brute force on the same random rays: the same hit
/// distances and primitive ids (bit for bit), and the same answers to any-hit queries.
class EveryAccel : public testing::TestWithParam<std::string> {};

TEST_P(EveryAccel, SameHitsAsBruteForceOnRandomRays) {
    Geometry g = random_geometry(3000, 200, 42);
    std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 2);
    ASSERT_TRUE(accel);
    BruteForce brute(g);
    Rng rng(7, 7);
    int hits = 0;
    for (int k = 0; k < 20000; ++k) {
        vec3 o(rng.next_float() * 1.4f - 0.2f, rng.next_float() * 1.4f - 0.2f,
               rng.next_float() * 1.4f - 0.2f);
        vec3 d(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
        if (k % 10 == 0) d = vec3(0.0f, 0.0f, d.z);  // axis-parallel rays too
        if (glm::length(d) == 0.0f) continue;
        Ray ray{o, glm::normalize(d), k % 5 == 0 ? 0.3f : kInfinity};
        Hit a, b;
        bool ha = accel->intersect(ray, a), hb = brute.intersect(ray, b);
        ASSERT_EQ(ha, hb) << "ray " << k << " prim " << b.prim << " t " << b.t << " kind "
                          << (g.is_triangle(b.prim) ? -1 : static_cast<int>(g.shape(b.prim).kind))
                          << " p " << glm::to_string(ray.o + b.t * ray.d) << " part " << b.part;
        if (ha) {
            ++hits;
            EXPECT_EQ(a.t, b.t) << "ray " << k;
            EXPECT_EQ(a.prim, b.prim) << "ray " << k;
            EXPECT_EQ(a.u, b.u) << "ray " << k;
            EXPECT_EQ(a.part, b.part) << "ray " << k;
        }
        ASSERT_EQ(accel->occluded(ray), hb) << "ray " << k;
    }
    EXPECT_GT(hits, 2000);  // the test exercises real hits
}

// The filtered any-hit query (Accel::occluded_if, the cutouts' shadow rays): blocked exactly
// when brute force finds a triangle the filter counts (here those whose id is not a multiple of
// three) or a shape before tmax; each hit the filter is asked about is that triangle's own hit.
TEST_P(EveryAccel, FilteredAnyHitCountsWhatTheFilterCounts) {
    Geometry g = random_geometry(3000, 200, 43);
    std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 2);
    ASSERT_TRUE(accel);
    if (!accel->filters_hits()) GTEST_SKIP() << GetParam() << " has no filtered query";
    struct Asked {
        const Geometry* g;
        int mismatches = 0, asked = 0;
    } asked{&g};
    const auto counts = [](const void* context, const Ray& ray, const Hit& hit) {
        auto* a = static_cast<Asked*>(const_cast<void*>(context));
        ++a->asked;
        Hit own;
        own.t = ray.tmax;
        const RayPrecomputed pre(ray);
        if (!a->g->is_triangle(hit.prim) || !a->g->intersect(&hit.prim, 1, ray, pre, own) ||
            own.t != hit.t || own.u != hit.u || own.v != hit.v)
            ++a->mismatches;
        return hit.prim % 3 != 0;
    };
    Rng rng(8, 8);
    int blocked = 0, passed_a_hit = 0;
    for (int k = 0; k < 20000; ++k) {
        const vec3 o(rng.next_float() * 1.4f - 0.2f, rng.next_float() * 1.4f - 0.2f,
                     rng.next_float() * 1.4f - 0.2f);
        const vec3 d(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
        if (glm::length(d) == 0.0f) continue;
        const Ray ray{o, glm::normalize(d), k % 5 == 0 ? 0.3f : kInfinity};
        const RayPrecomputed pre(ray);
        bool expected = false, any = false;
        for (uint32_t id = 0; id < g.primitive_count(); ++id) {
            Hit h;
            h.t = ray.tmax;
            if (!g.intersect(&id, 1, ray, pre, h)) continue;
            any = true;
            expected = expected || !g.is_triangle(id) || id % 3 != 0;
        }
        const bool got = accel->occluded_if(ray, HitFilter{counts, &asked});
        ASSERT_EQ(got, expected) << "ray " << k;
        blocked += got;
        passed_a_hit += any && !got;
    }
    EXPECT_EQ(asked.mismatches, 0);
    EXPECT_GT(blocked, 2000);
    EXPECT_GT(passed_a_hit, 100);  // rays that met only triangles the filter let through
}

/// The twelve triangles of the cube [lo, lo + 1]^3.
Geometry cube_at(float lo) {
    Geometry g;
    const float hi = lo + 1.0f;
    for (int k = 0; k < 8; ++k)
        g.positions.emplace_back(k & 1 ? hi : lo, k & 2 ? hi : lo, k & 4 ? hi : lo);
    const uint32_t faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                  {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    for (const auto& f : faces) {
        for (uint32_t v : {f[0], f[1], f[2], f[0], f[2], f[3]}) g.indices.push_back(v);
        g.triangle_material.insert(g.triangle_material.end(), {0u, 0u});
    }
    return g;
}

TEST_P(EveryAccel, ARayAlongABoxFaceMeetsTheEdgeAheadOfIt) {
    // A ray in the plane of the cube's top face (its direction's z exactly 0, its origin's z
    // the face's) meets the side face's top edge, as the watertight test finds it. A tight box
    // answered no: the slab's exit (hi - o) / d was 0 * 1e32 = 0 (the boxes are now a ulp
    // wider, bvh_build.cpp). Near the origin and at coordinates of a few hundred units, along
    // each axis, both ways.
    for (float lo : {0.0f, 200.0f, -300.0f}) {
        const Geometry g = cube_at(lo);
        std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 2);
        ASSERT_TRUE(accel);
        BruteForce brute(g);
        const float hi = lo + 1.0f, mid = lo + 0.5f;
        for (int axis = 0; axis < 3; ++axis) {
            for (float sign : {1.0f, -1.0f}) {
                const int up = (axis + 2) % 3;  // the face the ray runs along: up = hi
                vec3 o(mid), d(0.0f);
                o[axis] = sign > 0.0f ? lo - 0.5f : hi + 0.5f;
                o[up] = hi;
                d[axis] = sign;
                const Ray ray{o, d, kInfinity};
                Hit a, b;
                ASSERT_TRUE(brute.intersect(ray, b)) << lo << " " << axis << " " << sign;
                ASSERT_TRUE(accel->intersect(ray, a))
                    << "missed: cube at " << lo << ", along axis " << axis << " sign " << sign;
                EXPECT_EQ(a.t, b.t);
                EXPECT_TRUE(accel->occluded(ray)) << lo << " " << axis << " " << sign;
            }
        }
    }
}

/// Shadow rays toward one point (Accel::occluded_toward), as the rasterizer casts them: the
/// same answers as occluded() ray by ray, for packets that sweep narrow shafts (a patch of
/// nearby origins), wide ones (origins all over, on both sides of the end, which the wide
/// BVH cuts into narrower packets), rays that graze the triangles (origins at their
/// vertices and edges, the end at a vertex), and counts around the 64 rays of a packet.
TEST_P(EveryAccel, RaysTowardOnePointAnswerAsOneByOne) {
    Geometry g = random_geometry(3000, 200, 43);
    std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 2);
    ASSERT_TRUE(accel);
    Rng rng(11, 3);
    auto rnd = [&] { return rng.next_float(); };
    auto vertex = [&] {
        return g.positions[std::min<size_t>(static_cast<size_t>(rnd() * g.positions.size()),
                                            g.positions.size() - 1)];
    };
    int blocked = 0, open = 0;
    for (int round = 0; round < 60; ++round) {
        const int kind = round % 4;
        const vec3 end = kind == 3
                             ? vertex()
                             : vec3(rnd() * 1.6f - 0.3f, rnd() * 1.6f - 0.3f, rnd() * 1.6f - 0.3f);
        const size_t count = std::vector<size_t>{1, 7, 63, 64, 65, 200}[round % 6];
        const vec3 corner(rnd(), rnd(), rnd());
        std::vector<Ray> rays;
        for (size_t k = 0; k < count; ++k) {
            vec3 o;
            if (kind == 0) {  // an 8 x 8 patch, 2 mm apart
                o = corner +
                    0.002f * vec3(static_cast<float>(k % 8), static_cast<float>(k / 8 % 8), 0.0f);
            } else if (kind == 1) {  // anywhere
                o = vec3(rnd() * 1.6f - 0.3f, rnd() * 1.6f - 0.3f, rnd() * 1.6f - 0.3f);
            } else {  // on the triangles: their vertices and the middles of their edges
                const size_t t = std::min<size_t>(static_cast<size_t>(rnd() * 3000.0f), 2999);
                const vec3 a = g.positions[g.indices[3 * t]], b = g.positions[g.indices[3 * t + 1]];
                o = k % 2 ? a : 0.5f * (a + b);
            }
            rays.push_back(Ray{o, end - o, 1.0f});
        }
        std::vector<char> together(count);
        static_assert(sizeof(bool) == sizeof(char));
        accel->occluded_toward(end, rays.data(), count, reinterpret_cast<bool*>(together.data()));
        for (size_t k = 0; k < count; ++k) {
            const bool alone = accel->occluded(rays[k]);
            ASSERT_EQ(static_cast<bool>(together[k]), alone)
                << "round " << round << " ray " << k << " from " << glm::to_string(rays[k].o)
                << " to " << glm::to_string(end);
            (alone ? blocked : open)++;
        }
    }
    EXPECT_GT(blocked, 1000);  // both answers are exercised
    EXPECT_GT(open, 1000);
}

/// Shadow rays toward one point may name primitives they cannot meet (Accel::occluded_toward's
/// `skip`: the rasterizer's rays leaving a convex object), which a structure may leave
/// untested. Where those primitives do not change a ray's answer (it is the same with them
/// moved away), the answer is occluded()'s; where they do, it is one of the two. The wide BVH
/// does leave them untested: with every primitive skipped, nothing blocks a ray.
TEST_P(EveryAccel, RaysTowardOnePointMayLeaveWhatTheySkipUntested) {
    const Geometry g = random_geometry(3000, 200, 44);
    std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 2);
    ASSERT_TRUE(accel);
    Rng rng(12, 5);
    auto rnd = [&] { return rng.next_float(); };
    int decided = 0, either = 0;
    for (int round = 0; round < 6; ++round) {
        // Triangles [first, first + 600) skipped by every other ray, and moved away for the
        // answer without them.
        const auto first = static_cast<uint32_t>(rnd() * 2400.0f);
        const PrimitiveRange range{first, first + 600};
        Geometry without = g;
        for (uint32_t t = range.first; t < range.end; ++t)
            for (int v = 0; v < 3; ++v) without.positions[without.indices[3 * t + v]].x += 100.0f;
        std::unique_ptr<Accel> reduced = make_accel(GetParam(), without, 2);
        const vec3 end(rnd(), rnd(), rnd());
        std::vector<Ray> rays;
        std::vector<PrimitiveRange> skip;
        for (int k = 0; k < 130; ++k) {
            const vec3 o(rnd(), rnd(), rnd());
            rays.push_back(Ray{o, end - o, 1.0f});
            skip.push_back(k % 2 ? range : PrimitiveRange{});
        }
        std::vector<char> together(rays.size());
        accel->occluded_toward(end, rays.data(), rays.size(),
                               reinterpret_cast<bool*>(together.data()), skip.data());
        for (size_t k = 0; k < rays.size(); ++k) {
            const bool all = accel->occluded(rays[k]), rest = reduced->occluded(rays[k]);
            const bool answer = together[k] != 0;
            if (k % 2 == 0 || all == rest) {
                ASSERT_EQ(answer, all) << "round " << round << " ray " << k;
                ++decided;
            } else {
                ASSERT_TRUE(answer == all || answer == rest) << "round " << round << " ray " << k;
                ++either;
            }
        }
    }
    EXPECT_GT(decided, 300);
    EXPECT_GT(either, 10);  // rays that only the skipped triangles block
    const auto* wide = dynamic_cast<const WideBvh*>(accel.get());
    if (!wide || wide->width() == 16) return;  // (sixteen lanes: ray by ray, nothing skipped)
    // Every primitive skipped by a packet that sweeps one narrow shaft (an 8 x 8 patch of
    // origins, 2 mm apart, as a tile's samples): none is tested, and nothing blocks. (A ray
    // that a packet leaves alone is traced by occluded(), which tests everything.)
    const vec3 end(0.5f, 0.5f, 1.2f);
    std::vector<Ray> rays;
    for (int k = 0; k < 64; ++k) {
        const vec3 o = vec3(0.45f, 0.45f, -0.2f) +
                       0.002f * vec3(static_cast<float>(k % 8), static_cast<float>(k / 8), 0.0f);
        rays.push_back(Ray{o, end - o, 1.0f});
    }
    const std::vector<PrimitiveRange> everything(rays.size(),
                                                 PrimitiveRange{0, g.primitive_count()});
    bool blocked[64];
    accel->occluded_toward(end, rays.data(), rays.size(), blocked, everything.data());
    int any = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
        EXPECT_FALSE(blocked[k]) << k;
        any += accel->occluded(rays[k]) ? 1 : 0;
    }
    EXPECT_GT(any, 5);  // without the skip, some are blocked
}

/// A packet toward E = 0 whose one ray crosses a triangle 1e-6 inside its corner, at the edge
/// of the packet's shaft (the other 63 pass by, close): the triangle's box touches
/// the shaft only there and must not be culled. Every side and axis of the setup, mirrored
/// and rotated, so that each of the shaft's planes is the one that touches.
TEST_P(EveryAccel, RaysTowardOnePointKeepTheBoxAtTheShaftsEdge) {
    for (int axes = 0; axes < 3; ++axes) {
        for (int signs = 0; signs < 8; ++signs) {
            auto place = [&](vec3 q) {  // the setup's frame to the world's
                vec3 r;
                for (int c = 0; c < 3; ++c)
                    r[(c + axes) % 3] = (signs >> c & 1 ? -1.0f : 1.0f) * q[c];
                return r;
            };
            Geometry g;
            auto triangle = [&](vec3 a, vec3 b, vec3 c) {
                for (vec3 v : {a, b, c}) {
                    g.positions.push_back(place(v));
                    g.indices.push_back(static_cast<uint32_t>(g.positions.size() - 1));
                }
                g.triangle_material.push_back(0);
            };
            triangle(vec3(0, 0, 1), vec3(1, 0, 1), vec3(0, 1, 1));
            Rng rng(5, static_cast<uint64_t>(8 * axes + signs));
            for (int k = 0; k < 300; ++k) {  // far away, so that the tree has inner nodes
                vec3 c(rng.next_float() * 40.0f + 20.0f, rng.next_float() * 40.0f - 20.0f,
                       rng.next_float() * 40.0f);
                triangle(c, c + vec3(0.5f, 0, 0), c + vec3(0, 0.5f, 0));
            }
            std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 1);
            const vec3 end(0.0f);
            std::vector<Ray> rays;
            // Crossing z = 1 at x, y in [-0.08, -0.01]: a narrow packet, one shaft.
            for (int k = 0; k < 63; ++k) {
                const vec3 o(-0.02f - 0.14f * static_cast<float>(k % 8) / 7.0f,
                             -0.02f - 0.14f * static_cast<float>(k / 8) / 7.0f, 2.0f);
                rays.push_back(Ray{place(o), end - place(o), 1.0f});
            }
            const vec3 o(2e-6f, 2e-6f, 2.0f);  // crossing z = 1 at (1e-6, 1e-6)
            rays.push_back(Ray{place(o), end - place(o), 1.0f});
            bool together[64];
            accel->occluded_toward(end, rays.data(), rays.size(), together);
            for (size_t k = 0; k < rays.size(); ++k) {
                ASSERT_EQ(together[k], k == 63)
                    << "axes " << axes << " signs " << signs << " ray " << k;
                ASSERT_EQ(accel->occluded(rays[k]), k == 63);
            }
        }
    }
}

TEST_P(EveryAccel, EmptyAndDegenerateInputs) {
    Geometry empty;
    std::unique_ptr<Accel> none = make_accel(GetParam(), empty, 1);
    Hit hit;
    EXPECT_FALSE(none->intersect(Ray{}, hit));
    EXPECT_FALSE(none->occluded(Ray{}));
    Geometry g;  // 100 identical triangles in a plane: centroids coincide, bounds are flat
    for (int k = 0; k < 100; ++k) {
        g.positions.insert(g.positions.end(), {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)});
        for (int v = 0; v < 3; ++v) g.indices.push_back(static_cast<uint32_t>(3 * k + v));
        g.triangle_material.push_back(0);
    }
    std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 1);
    ASSERT_TRUE(accel->intersect(Ray{vec3(0.2f, 0.2f, 1.0f), vec3(0, 0, -1)}, hit));
    EXPECT_EQ(hit.t, 1.0f);
    EXPECT_LT(hit.prim, 100u);  // coincident triangles: any of them
    EXPECT_FALSE(accel->intersect(Ray{vec3(0.8f, 0.8f, 1.0f), vec3(0, 0, -1)}, hit));
    EXPECT_TRUE(accel->occluded(Ray{vec3(0.2f, 0.2f, -1.0f), vec3(0, 0, 1)}));
}

// Coordinates near the float limit, where the sum of a triangle's bounds overflows (a centroid
// of 2e38 and 3e38 is inf), and a few that are infinite, such as a generated square around a
// scene 6e38 wide (radiosity's stand-in for an infinite plane): the build must not index
// bins with NaN or inf (it crashed), and the finite triangles are still found.
TEST_P(EveryAccel, CoordinatesNearAndPastTheFloatLimitBuild) {
    Geometry g;
    const float inf = std::numeric_limits<float>::infinity();
    for (int k = 0; k < 200; ++k) {
        float x = k < 100 ? 2e38f + 1e36f * static_cast<float>(k) : -3e38f;
        float z = -static_cast<float>(k);
        vec3 far = k % 50 == 7 ? vec3(inf, 0, z) : vec3(x + 1e36f, 0, z);
        g.positions.insert(g.positions.end(), {vec3(x, -1e37f, z), far, vec3(x, 1e37f, z)});
        for (int v = 0; v < 3; ++v) g.indices.push_back(static_cast<uint32_t>(3 * k + v));
        g.triangle_material.push_back(0);
    }
    // A small triangle among them, in front of the others.
    g.positions.insert(g.positions.end(), {vec3(-1, -1, 1), vec3(1, -1, 1), vec3(0, 1, 1)});
    for (int v = 0; v < 3; ++v) g.indices.push_back(static_cast<uint32_t>(600 + v));
    g.triangle_material.push_back(0);
    std::unique_ptr<Accel> accel = make_accel(GetParam(), g, 2);
    Hit hit;
    ASSERT_TRUE(accel->intersect(Ray{vec3(0, 0, 5), vec3(0, 0, -1)}, hit));
    EXPECT_EQ(hit.prim, 200u);
    EXPECT_NEAR(hit.t, 4.0f, 1e-5f);
}

INSTANTIATE_TEST_SUITE_P(Accel, EveryAccel, testing::ValuesIn(accel_names()),
                         [](const testing::TestParamInfo<std::string>& param) {
                             return param.param;
                         });

TEST(Accel, NamesIncludeEveryStructure) {
    std::vector<std::string> names = accel_names();
    for (const char* name : {"none", "grid", "octree", "bvh2", "bvh"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
    }
    EXPECT_EQ(make_accel("kd-tree", Geometry{}), nullptr);
}

/// Every primitive of `g` sits in exactly one leaf of `bvh` whose box contains it, and every
/// inner box contains its children's.
void expect_valid(const Geometry& g, const Bvh& bvh) {
    const auto& nodes = bvh.nodes();
    std::vector<int> seen(g.primitive_count(), 0);
    // Every primitive sits in exactly one leaf whose box contains it.
    for (const BvhNode& n : nodes) {
        if (n.count == 0) {
            for (uint32_t c : {n.first, n.first + 1}) {
                EXPECT_TRUE(glm::all(glm::lessThanEqual(n.min, nodes[c].min)));
                EXPECT_TRUE(glm::all(glm::greaterThanEqual(n.max, nodes[c].max)));
            }
            continue;
        }
        EXPECT_LE(n.count, 8u);
        for (uint32_t k = n.first; k < n.first + n.count; ++k) {
            uint32_t id = bvh.primitives()[k];
            seen[id]++;
            Bounds3 b = g.primitive_bounds(id);
            EXPECT_TRUE(glm::all(glm::lessThanEqual(n.min, b.min)));
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(n.max, b.max)));
        }
    }
    for (int s : seen) EXPECT_EQ(s, 1);
    EXPECT_LT(bvh.depth(), 64);
}

TEST(Bvh, StructureIsValid) {
    Geometry g = random_geometry(5000, 50, 3);
    expect_valid(g, Bvh(g, 1));
}

// Triangles in denormal coordinates (below 1.2e-38): the binning's scale, 16 / extent,
// overflows to infinity, and halving a coordinate rounds, so positions are infinite or NaN.
// Every reference must still land in a bin (bin() masks its index: without it this test
// crashes) and the tree must hold every triangle, on one thread and two.
TEST(Bvh, DenormalSizedTrianglesBuildAValidTree) {
    Geometry g = random_geometry(3000, 0, 5);
    for (vec3& p : g.positions) p *= 1e-39f;
    for (int threads : {1, 2}) expect_valid(g, Bvh(g, threads));
}

/// The tree of `bvh` below `node` as text: every box, and every leaf's primitive ids sorted (a
/// leaf's order, and where the nodes lie in memory, may depend on the threads).
void describe(const Bvh& bvh, uint32_t node, std::ostringstream& out) {
    const BvhNode& n = bvh.nodes()[node];
    out << glm::to_string(n.min) << glm::to_string(n.max);
    if (n.count == 0) {
        out << '(';
        describe(bvh, n.first, out);
        describe(bvh, n.first + 1, out);
        out << ')';
        return;
    }
    std::vector<uint32_t> ids(bvh.primitives().begin() + n.first,
                              bvh.primitives().begin() + n.first + n.count);
    std::sort(ids.begin(), ids.end());
    for (uint32_t id : ids) out << ' ' << id;
    out << ';';
}

std::string describe(const Bvh& bvh) {
    std::ostringstream out;
    describe(bvh, 0, out);
    return out.str();
}

TEST(Bvh, SameTreeOnOneAndTwoThreads) {
    // Enough primitives that the top nodes are binned and partitioned in parallel chunks.
    Geometry g = random_geometry(150000, 20, 4);
    Bvh one(g, 1), two(g, 2);
    EXPECT_EQ(describe(one), describe(two));
}

/// The number of primitives below `node`.
uint32_t primitives_below(const Bvh& bvh, uint32_t node) {
    const BvhNode& n = bvh.nodes()[node];
    if (n.count > 0) return n.count;
    return primitives_below(bvh, n.first) + primitives_below(bvh, n.first + 1);
}

TEST(Bvh, SmallNodesSplitAtTheCheapestPlaneOnTheirAxis) {
    // 9 to 16 triangles (too many for one leaf) are sorted rather than binned: the root's split
    // must cost exactly the least area x count over the splits between sorted centroids on the
    // axis of largest centroid extent, where 16 bins would merge close centroids.
    for (uint64_t seed = 0; seed < 50; ++seed) {
        Rng rng(seed, 7);
        const int n = 9 + static_cast<int>(seed % 8);
        Geometry g = random_geometry(n, 0, seed);
        // Squeeze half the centroids together so that several share one bin's width.
        for (int k = 0; k < n / 2; ++k)
            for (int v = 0; v < 3; ++v) g.positions[3 * k + v].x *= 0.02f;
        Bvh bvh(g, 1);
        const BvhNode& root = bvh.nodes()[0];
        ASSERT_EQ(root.count, 0u) << seed;
        std::vector<Bounds3> boxes;
        Bounds3 centroids;
        for (uint32_t id = 0; id < static_cast<uint32_t>(n); ++id) {
            boxes.push_back(g.primitive_bounds(id));
            centroids.extend(boxes.back().center());
        }
        const int axis = max_dimension(centroids.extent());
        std::sort(boxes.begin(), boxes.end(), [axis](const Bounds3& a, const Bounds3& b) {
            return a.center()[axis] < b.center()[axis];
        });
        double best = std::numeric_limits<double>::infinity();
        for (int split = 1; split < n; ++split) {
            Bounds3 l, r;
            for (int k = 0; k < n; ++k) (k < split ? l : r).extend(boxes[k]);
            best = std::min(best, static_cast<double>(l.surface_area()) * split +
                                      static_cast<double>(r.surface_area()) * (n - split));
        }
        auto area = [&](uint32_t node) {
            const BvhNode& c = bvh.nodes()[node];
            return static_cast<double>(Bounds3{c.min, c.max}.surface_area());
        };
        const double cost = area(root.first) * primitives_below(bvh, root.first) +
                            area(root.first + 1) * primitives_below(bvh, root.first + 1);
        EXPECT_NEAR(cost, best, 1e-6 * best) << "seed " << seed << ", " << n << " triangles";
    }
}

// A closed room of six quads, seen from inside: every ray meets one wall, and each wall's
// box is flat, so a tree with a leaf per wall tests one quad a ray. Weighed as triangles (a
// leaf of up to four without a SAH test, a test as cheap as a node's) the six shared one leaf
// and every ray tested all six.
TEST(WideBvh, RaysInARoomOfQuadsTestOneWall) {
    Geometry g;
    const vec3 lo(-2.0f, 0.0f, -2.0f), size(4.0f, 2.6f, 4.0f);
    const vec3 x(size.x, 0, 0), y(0, size.y, 0), z(0, 0, size.z);
    const std::pair<vec3, vec3> walls[6] = {{z, x}, {x, z}, {x, y}, {y, x}, {y, z}, {z, y}};
    for (int k = 0; k < 6; ++k) {
        // Floor, ceiling, back, front, left, right: the second of each pair moved across.
        const vec3 corner = lo + (k % 2 == 1 ? vec3(k < 2 ? y : k < 4 ? z : x) : vec3(0.0f));
        g.shapes.push_back(
            make_analytic_shape(Quad{corner, walls[k].first, walls[k].second}, Transform{}, 0));
    }
    for (int width : {4, 8}) {
        WideBvh bvh(g, 1, width);
        Rng rng(9, 2);
        uint32_t tested = 0;
        const int rays = 1000;
        for (int k = 0; k < rays; ++k) {
            const vec3 d = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
            const vec3 o = lo + vec3(0.2f + 3.6f * rng.next_float(), 0.2f + 2.2f * rng.next_float(),
                                     0.2f + 3.6f * rng.next_float());
            Hit hit;
            TraversalCost cost;
            ASSERT_TRUE(bvh.intersect_cost(Ray{o, d}, hit, cost)) << k;
            tested += cost.primitives;
        }
        EXPECT_LT(static_cast<double>(tested) / rays, 1.5) << width << " wide";
    }
}

TEST(Bvh, DegenerateInputsBuild) {
    Geometry g;
    for (int k = 0; k < 100; ++k) {  // 100 identical triangles: centroids coincide
        g.positions.insert(g.positions.end(), {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)});
        for (int v = 0; v < 3; ++v) g.indices.push_back(static_cast<uint32_t>(3 * k + v));
        g.triangle_material.push_back(0);
    }
    Bvh bvh(g);
    Hit hit;
    EXPECT_TRUE(bvh.intersect(Ray{vec3(0.2f, 0.2f, 1.0f), vec3(0, 0, -1)}, hit));
    EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
    Geometry empty;
    Bvh none(empty);
    EXPECT_FALSE(none.intersect(Ray{}, hit));
    EXPECT_FALSE(none.occluded(Ray{}));
}

}  // namespace
}  // namespace svetlo
