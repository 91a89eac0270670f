#include "svetlo/geometry/occluder_cube.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>

#include "svetlo/core/rng.h"
#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/ray.h"

namespace svetlo {
namespace {

/// Appends triangle (a, b, c) to the list.
void add_triangle(TriangleList& list, vec3 a, vec3 b, vec3 c) {
    for (vec3 p : {a, b, c}) {
        list.indices.push_back(static_cast<uint32_t>(list.positions.size()));
        list.positions.push_back(p);
    }
    list.material.push_back(0);
}

/// Objects of every kind a cube must hold: a floor under the end E, small and large
/// triangles around it, one that passes a hair from E, and one in whose plane E nearly lies
/// and that spans several faces of the cube.
TriangleList scene_around(vec3 end, uint64_t seed) {
    TriangleList list;
    Rng rng(seed, 3);
    auto rnd = [&] { return rng.next_float() * 2.0f - 1.0f; };
    auto object = [&](auto&& add) {
        const auto first = static_cast<uint32_t>(list.triangle_count());
        add();
        list.objects.push_back({first, static_cast<uint32_t>(list.triangle_count())});
    };
    object([&] {  // the floor, y = -1
        add_triangle(list, {-3, -1, -3}, {-3, -1, 3}, {3, -1, 3});
        add_triangle(list, {-3, -1, -3}, {3, -1, 3}, {3, -1, -3});
    });
    object([&] {  // small triangles
        for (int k = 0; k < 300; ++k) {
            const vec3 c(rnd(), rnd(), rnd());
            add_triangle(list, c, c + 0.05f * vec3(rnd(), rnd(), rnd()),
                         c + 0.05f * vec3(rnd(), rnd(), rnd()));
        }
    });
    object([&] {  // large ones
        for (int k = 0; k < 12; ++k) {
            const vec3 c(rnd(), rnd(), rnd());
            add_triangle(list, c, c + 0.6f * vec3(rnd(), rnd(), rnd()),
                         c + 0.6f * vec3(rnd(), rnd(), rnd()));
        }
    });
    object([&] {  // a hair from E
        add_triangle(list, end + vec3(0.001f, -0.3f, -0.3f), end + vec3(0.001f, 0.3f, -0.3f),
                     end + vec3(0.001f, 0.0f, 0.4f));
    });
    object([&] {  // E nearly in its plane, across several faces
        add_triangle(list, end + vec3(-0.9f, 0.2f, 0.5f), end + vec3(0.9f, -0.2f, 0.6f),
                     end + vec3(0.1f, 1e-4f, -0.9f));
    });
    return list;
}

/// The list as ray-traceable geometry, object `moved` (if any) moved far off, where no
/// segment of the test passes.
std::unique_ptr<Accel> accel_without(const TriangleList& list, int moved) {
    Geometry g = triangle_geometry(list);
    if (moved >= 0) {
        const PrimitiveRange r = list.objects[static_cast<size_t>(moved)];
        for (uint32_t t = r.first; t < r.end; ++t)
            for (int v = 0; v < 3; ++v) g.positions[g.indices[3 * t + v]].x += 1000.0f;
    }
    return make_accel("bvh", g, 1);
}

/// A sample on triangle t of the list: a point inside it, on the side that faces `end` (or
/// the other side, one time in five), as the rasterizer's samples are.
struct Sample {
    vec3 p, n;
    uint32_t triangle;
};
Sample sample_on(const TriangleList& list, uint32_t t, vec3 end, Rng& rng) {
    const vec3 a = list.positions[list.indices[3 * t]], b = list.positions[list.indices[3 * t + 1]],
               c = list.positions[list.indices[3 * t + 2]];
    const float u = rng.next_float(), v = rng.next_float() * (1.0f - u);
    const vec3 p = a + u * (b - a) + v * (c - a);
    vec3 n = glm::normalize(glm::cross(b - a, c - a));
    if (glm::dot(n, end - p) < 0.0f) n = -n;
    return {p, rng.next_float() < 0.8f ? n : -n, t};
}

/// Whether the shadow ray of sample s toward `end` is blocked, as the rasterizer traces it:
/// from a hair off the surface (offset_ray_origin) and a step toward the end, its own object
/// skipped where the ray leaves it (leaves_convex).
bool blocked(const TriangleList& list, const std::vector<std::unique_ptr<Accel>>& without,
             const Sample& s, vec3 end) {
    const vec3 wi = glm::normalize(end - s.p);
    const float toward =
        std::max({std::abs(s.p.x), std::abs(s.p.y), std::abs(s.p.z), 1.0f}) / 65536.0f;
    const vec3 o = offset_ray_origin(s.p, s.n, wi) + toward * wi;
    int skipped = -1;
    for (size_t k = 0; k < list.objects.size(); ++k)
        if (s.triangle >= list.objects[k].first && s.triangle < list.objects[k].end &&
            leaves_convex(list.convex[k] != 0, list.centroid[k], s.p, s.n))
            skipped = static_cast<int>(k);
    return without[static_cast<size_t>(skipped + 1)]->occluded(Ray{o, end - o, 1.0f});
}

TEST(OccluderCube, NeverCallsClearARaySomethingBlocks) {
    const vec3 end(0.1f, 0.6f, -0.2f);
    TriangleList list = scene_around(end, 7);
    // The floor and the two sets of triangles count as convex, so that their samples' rays
    // skip them (their triangles then lie anywhere: the cube must still never be wrong for the
    // other objects').
    list.convex = {1, 0, 0, 0, 0};
    list.centroid.assign(list.objects.size(), vec3(0.0f, -1.0f, 0.0f));
    const OccluderCube cube(list, end, 2);
    const auto objects = static_cast<int>(list.objects.size());
    std::vector<std::unique_ptr<Accel>> without;  // [0]: all; [k + 1]: without object k
    for (int k = -1; k < objects; ++k) without.push_back(accel_without(list, k));
    Rng rng(11, 4);
    int clear = 0, open = 0, shadowed = 0;
    for (int n = 0; n < 60000; ++n) {
        const auto t =
            static_cast<uint32_t>(rng.next_float() * static_cast<float>(list.triangle_count())) %
            static_cast<uint32_t>(list.triangle_count());
        // The floor's samples most (most of a frame's), then any triangle's.
        const Sample s = sample_on(list, n % 2 ? t : t % 2, end, rng);
        const bool is_blocked = blocked(list, without, s, end);
        const bool is_clear = cube.clear(s.p, s.n, s.triangle);
        ASSERT_FALSE(is_clear && is_blocked) << "sample " << n << " on triangle " << s.triangle;
        shadowed += is_blocked ? 1 : 0;
        open += is_blocked ? 0 : 1;
        clear += is_clear ? 1 : 0;
    }
    // Both answers many times; and in this thicket around E, still a fair part of the open
    // rays known clear (the next test: most of them, in a room).
    EXPECT_GT(shadowed, 3000);
    EXPECT_GT(clear, open / 4) << clear << " of " << open;
}

TEST(OccluderCube, KnowsMostOpenRaysOfAFloorUnderALampClear) {
    // A floor 8 m wide, a cube 1 m wide on it, a lamp 3 m above: of the floor's samples that
    // the cube does not shadow, all but a rim round its shadow (a cell or two, a few cm) are
    // known clear.
    const vec3 end(0.3f, 3.0f, 0.2f);
    TriangleList list;
    list.objects.push_back({0, 2});
    add_triangle(list, {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4});
    add_triangle(list, {-4, 0, -4}, {4, 0, 4}, {4, 0, -4});
    const vec3 lo(-0.5f, 0.0f, -0.5f), hi(0.5f, 1.0f, 0.5f);
    for (int axis = 0; axis < 3; ++axis) {  // the cube's six faces
        for (float side : {lo[axis], hi[axis]}) {
            vec3 c[4];
            for (int k = 0; k < 4; ++k) {
                c[k][axis] = side;
                c[k][(axis + 1) % 3] = (k == 1 || k == 2) ? hi[(axis + 1) % 3] : lo[(axis + 1) % 3];
                c[k][(axis + 2) % 3] = k >= 2 ? hi[(axis + 2) % 3] : lo[(axis + 2) % 3];
            }
            add_triangle(list, c[0], c[1], c[2]);
            add_triangle(list, c[0], c[2], c[3]);
        }
    }
    list.objects.push_back({2, 14});
    list.convex = {1, 1};
    list.centroid = {vec3(0.0f), vec3(0.0f, 0.5f, 0.0f)};
    const OccluderCube cube(list, end, 1);
    std::vector<std::unique_ptr<Accel>> without;
    for (int k = -1; k < 2; ++k) without.push_back(accel_without(list, k));
    Rng rng(3, 8);
    int clear = 0, open = 0;
    for (int n = 0; n < 20000; ++n) {
        Sample s = sample_on(list, static_cast<uint32_t>(n % 2), end, rng);
        s.n = vec3(0.0f, 1.0f, 0.0f);
        const bool is_blocked = blocked(list, without, s, end);
        const bool is_clear = cube.clear(s.p, s.n, s.triangle);
        ASSERT_FALSE(is_clear && is_blocked) << n;
        open += is_blocked ? 0 : 1;
        clear += is_clear ? 1 : 0;
    }
    EXPECT_GT(clear, open * 99 / 100) << clear << " of " << open;
}

TEST(OccluderCube, IsTheSameOnOneAndTwoThreads) {
    const vec3 end(0.1f, 0.6f, -0.2f);
    const TriangleList list = scene_around(end, 9);
    const OccluderCube one(list, end, 1), two(list, end, 2);
    EXPECT_EQ(one.empty_cells(), two.empty_cells());
    Rng rng(5, 2);
    for (int n = 0; n < 20000; ++n) {
        const vec3 p = vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 4.0f - 2.0f;
        const vec3 dir =
            glm::normalize(vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f);
        const auto t = static_cast<uint32_t>(n) % static_cast<uint32_t>(list.triangle_count());
        ASSERT_EQ(one.clear(p, dir, t), two.clear(p, dir, t)) << n;
    }
}

TEST(OccluderCube, AnEmptyCubeOrAPointNotFiniteIsNeverClear) {
    const vec3 end(0.0f, 2.0f, 0.0f);
    EXPECT_FALSE(OccluderCube().clear(vec3(0.0f), vec3(0.0f, 1.0f, 0.0f), 0));
    TriangleList list;
    add_triangle(list, {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1});
    const OccluderCube cube(list, end, 1);
    EXPECT_TRUE(cube.clear(vec3(3.0f, 5.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 0));    // above: open
    EXPECT_FALSE(cube.clear(vec3(0.5f, -3.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 0));  // below it
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
    for (vec3 p : {vec3(nan, 5.0f, 0.0f), vec3(inf, 5.0f, 0.0f), vec3(0.0f, -inf, 0.0f), end})
        EXPECT_FALSE(cube.clear(p, vec3(0.0f, 1.0f, 0.0f), 0));
    // A triangle with a corner not finite, or beyond float's range once squared, may lie
    // anywhere: nothing is clear.
    for (vec3 far : {vec3(nan, 0.0f, 0.0f), vec3(inf, 1.0f, 0.0f), vec3(3e38f, -3e38f, 1.0f)}) {
        TriangleList wild = list;
        add_triangle(wild, far, {0.0f, 1.0f, 0.5f}, {0.5f, 1.0f, 0.0f});
        const OccluderCube wild_cube(wild, end, 1);
        EXPECT_FALSE(wild_cube.clear(vec3(3.0f, 5.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 0)) << far.x;
    }
}

}  // namespace
}  // namespace svetlo
