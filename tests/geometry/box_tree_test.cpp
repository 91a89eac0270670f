// The top level of instances (geometry/box_tree.h): every box a ray enters is offered to the
// caller, nearest first, in both widths, on spread, piled, flat and empty boxes, and boxes
// spaced so that the SAH would peel them off one at a time keep the tree shallow.
#include "svetlo/geometry/box_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "svetlo/core/rng.h"
#include "svetlo/geometry/ray_box.h"

namespace svetlo {
namespace {

vec3 random_point(Rng& rng, float scale) {
    return scale * vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
}

/// Boxes about the origin: some flat along an axis, one in ten empty.
std::vector<Bounds3> random_boxes(Rng& rng, int count) {
    std::vector<Bounds3> boxes(count);
    for (Bounds3& b : boxes) {
        if (rng.next_float() < 0.1f) continue;  // empty
        const vec3 c = random_point(rng, 6.0f);
        vec3 half = 0.5f * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        if (rng.next_float() < 0.2f) half[static_cast<int>(rng.next_float() * 3.0f) % 3] = 0.0f;
        b.extend(c - half);
        b.extend(c + half);
    }
    return boxes;
}

Ray random_ray(Rng& rng) {
    Ray ray;
    ray.o = random_point(rng, 10.0f);
    ray.d = random_point(rng, 4.0f) - ray.o;
    if (rng.next_float() < 0.2f) ray.d[static_cast<int>(rng.next_float() * 3.0f) % 3] = 0.0f;
    ray.tmax = rng.next_float() < 0.3f ? 2.0f * rng.next_float() : kInfinity;
    return ray;
}

/// A leaf's "hit": where the ray enters its box, when that is nearer than the hit so far.
struct EnterBox {
    const std::vector<Bounds3>& boxes;
    const Ray& ray;
    uint32_t* calls;
    bool operator()(uint32_t k, Hit& hit) const {
        ++*calls;
        const float t = box_entry(boxes[k].min, boxes[k].max, ray.o, safe_inverse(ray.d), hit.t);
        if (!(t < hit.t)) return false;
        hit.t = t;
        hit.prim = k;
        return true;
    }
};

/// The nearest entry over all boxes, by brute force (kInfinity when the ray enters none).
float nearest_entry(const std::vector<Bounds3>& boxes, const Ray& ray) {
    float best = kInfinity;
    for (const Bounds3& b : boxes) {
        if (b.empty()) continue;
        const float t = box_entry(b.min, b.max, ray.o, safe_inverse(ray.d), ray.tmax);
        if (t < ray.tmax) best = std::min(best, t);
    }
    return best;
}

class BoxTreeWidth : public ::testing::TestWithParam<int> {};

TEST_P(BoxTreeWidth, OffersTheNearestBoxAndAnyBoxTheRayEnters) {
    Rng rng(7, 1);
    for (int count : {1, 2, 7, 8, 9, 64, 500}) {
        const std::vector<Bounds3> boxes = random_boxes(rng, count);
        const BoxTree tree(boxes, GetParam());
        for (int r = 0; r < 400; ++r) {
            const Ray ray = random_ray(rng);
            const float expected = nearest_entry(boxes, ray);
            Hit hit;
            hit.t = ray.tmax;
            uint32_t calls = 0;
            const bool found = tree.closest(ray, hit, EnterBox{boxes, ray, &calls});
            ASSERT_EQ(found, expected < ray.tmax) << count << " boxes, ray " << r;
            if (found) {
                ASSERT_EQ(hit.t, expected) << count << " boxes, ray " << r;
            }
            const bool any = tree.any(ray, [&](uint32_t k) {
                const Bounds3& b = boxes[k];
                return box_entry(b.min, b.max, ray.o, safe_inverse(ray.d), ray.tmax) < ray.tmax;
            });
            ASSERT_EQ(any, found) << count << " boxes, ray " << r;
        }
    }
}

TEST_P(BoxTreeWidth, VisitsFewNodesAndCountsThem) {
    // A 32 x 32 field of unit boxes, and a ray straight down onto one of them: a handful of
    // nodes and one box, not the field.
    std::vector<Bounds3> boxes;
    for (int i = 0; i < 32; ++i) {
        for (int j = 0; j < 32; ++j) {
            Bounds3 b;
            b.extend(vec3(2.0f * i, 0.0f, 2.0f * j));
            b.extend(vec3(2.0f * i + 1.0f, 1.0f, 2.0f * j + 1.0f));
            boxes.push_back(b);
        }
    }
    const BoxTree tree(boxes, GetParam());
    EXPECT_EQ(tree.width(), GetParam() == 4 ? 4 : tree.width());
    const Ray ray{vec3(20.5f, 5.0f, 40.5f), vec3(0.0f, -1.0f, 0.0f), kInfinity};
    Hit hit;
    hit.t = ray.tmax;
    uint32_t calls = 0, visited = 0;
    ASSERT_TRUE(tree.closest(ray, hit, EnterBox{boxes, ray, &calls}, &visited));
    EXPECT_EQ(hit.prim, 10u * 32u + 20u);
    EXPECT_FLOAT_EQ(hit.t, 4.0f);
    EXPECT_EQ(calls, 1u);
    EXPECT_GE(visited, 2u);
    EXPECT_LE(visited, 8u);
}

TEST_P(BoxTreeWidth, BoxesTheSahWouldPeelOneByOneKeepTheTreeShallow) {
    // Unit boxes at x = 1.4^k: each binned split of the SAH cuts off the farthest few, so that
    // the SAH alone builds 27 (eight wide) and 31 (four wide) levels over 250 boxes, deeper
    // the more there are. Below its first 12 levels the tree splits at the median: each level
    // then halves the boxes at least once, so the depth stays under 12 + log2(count) (here
    // 20), and a tree of 2^31 boxes fits the traversal's stack (36 levels of 7 entries).
    std::vector<Bounds3> boxes;
    for (int k = 0; k < 250; ++k) {
        const float x = std::pow(1.4f, static_cast<float>(k));
        Bounds3 b;
        b.extend(vec3(x, 0.0f, 0.0f));
        b.extend(vec3(x + 1.0f, 1.0f, 1.0f));
        boxes.push_back(b);
    }
    const BoxTree tree(boxes, GetParam());
    EXPECT_LE(tree.depth(), 12 + 8);
    // Along the row from its near end, and straight down onto the middle of box 45 (at 3.8e6,
    // where a float still resolves the unit box; the farther boxes are flat).
    for (const auto& [o, d, first] :
         {std::tuple{vec3(-1.0f, 0.5f, 0.5f), vec3(1.0f, 0.0f, 0.0f), 0u},
          std::tuple{vec3(boxes[45].min.x + 0.5f, 5.0f, 0.5f), vec3(0.0f, -1.0f, 0.0f), 45u}}) {
        const Ray ray{o, d, kInfinity};
        Hit hit;
        hit.t = ray.tmax;
        uint32_t calls = 0;
        ASSERT_TRUE(tree.closest(ray, hit, EnterBox{boxes, ray, &calls}));
        EXPECT_EQ(hit.prim, first);
    }
}

TEST_P(BoxTreeWidth, ARayAlongABoxsFaceEntersIt) {
    // Along the top face of a unit cube (a placed cube's edge met along its face): the slab's
    // exit is (hi - o) / d = 0 * 1e32 without the ulp every structure adds (ray_box.h).
    const std::vector<Bounds3> boxes = {Bounds3{vec3(0.0f), vec3(1.0f)},
                                        Bounds3{vec3(3.0f), vec3(4.0f)}};
    const BoxTree tree(boxes, GetParam());
    const Ray ray{vec3(-1.0f, 1.0f, 0.5f), vec3(1.0f, 0.0f, 0.0f), kInfinity};
    std::vector<uint32_t> offered;
    EXPECT_FALSE(tree.any(ray, [&](uint32_t k) {
        offered.push_back(k);
        return false;
    }));
    EXPECT_EQ(offered, std::vector<uint32_t>{0u});
}

TEST_P(BoxTreeWidth, BoxesReachingInfinityAreBuiltAndTraversed) {
    // Boxes flat in y = 0 and reaching x = inf (placements whose transforms overflow): the box
    // of any two of them has area NaN (inf times 0), which must not stop the build from
    // splitting them (it recursed into the same boxes without end).
    std::vector<Bounds3> boxes;
    for (int k = 0; k < 20; ++k) {
        Bounds3 b;
        b.extend(vec3(0.0f, 0.0f, static_cast<float>(k)));
        b.extend(vec3(kInfinity, 0.0f, static_cast<float>(k) + 1.0f));
        boxes.push_back(b);
    }
    Bounds3 unit;
    unit.extend(vec3(-3.0f, 0.0f, -1.0f));
    unit.extend(vec3(-2.0f, 1.0f, 0.0f));
    boxes.push_back(unit);
    const BoxTree tree(boxes, GetParam());
    const Ray ray{vec3(-2.5f, 5.0f, -0.5f), vec3(0.0f, -1.0f, 0.0f), kInfinity};
    Hit hit;
    hit.t = ray.tmax;
    uint32_t calls = 0;
    ASSERT_TRUE(tree.closest(ray, hit, EnterBox{boxes, ray, &calls}));
    EXPECT_EQ(hit.prim, 20u);
}

INSTANTIATE_TEST_SUITE_P(Widths, BoxTreeWidth, ::testing::Values(4, 8));

}  // namespace
}  // namespace svetlo
