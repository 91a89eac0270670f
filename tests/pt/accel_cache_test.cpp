// One BVH for the renders of one command (geometry/accel_cache.h, docs/compare.md "One
// scene, one BVH"): scenes whose shapes are the same share it, scenes whose shapes differ
// do not, and an image rendered with a shared structure is bit for bit the image rendered
// with its own.
#include "svetlo/geometry/accel_cache.h"

#include <gtest/gtest.h>

#include "svetlo/core/error.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/rt/rt_scene.h"
#include "svetlo/rt/whitted.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

const char* kSpheres = SVETLO_SCENES "/spheres.json";

/// scenes/spheres.json (an area light, a point light, five shapes) with `overrides`, small.
Scene spheres(std::vector<Override> overrides = {}) {
    overrides.insert(overrides.begin(), {{"film.width", "48"}, {"film.height", "32"}});
    return load_scene(kSpheres, overrides);
}

TEST(AccelCache, ScenesWithTheSameShapesShareOneStructure) {
    AccelCache cache;
    const Scene a = spheres();
    // What moves no shape: a material, the point light, the samples.
    const Scene b = spheres({{"materials.red.kd", "[0.1, 0.9, 0.1]"},
                             {"lights.1.position", "[1, 6, 2]"},
                             {"render.spp", "3"}});
    EXPECT_EQ(a.geometry_key, b.geometry_key);
    RtScene ra(a, "bvh", 2, &cache);
    RtScene rb(b, "bvh", 1, &cache);
    EXPECT_EQ(&ra.accel(), &rb.accel());
    EXPECT_EQ(&ra.geometry(), &rb.geometry());
    EXPECT_EQ(cache.builds(), 1);
}

TEST(AccelCache, ScenesWithOtherShapesOrStructuresBuildTheirOwn) {
    AccelCache cache;
    const Scene a = spheres();
    RtScene ra(a, "bvh", 2, &cache);
    // A shape, the area light's quad (it is geometry), the structure's name.
    const Scene moved = spheres({{"objects.1.radius", "0.25"}});
    const Scene area = spheres({{"lights.0.corner", "[-1, 3.5, -1]"}});
    EXPECT_NE(a.geometry_key, moved.geometry_key);
    EXPECT_NE(a.geometry_key, area.geometry_key);
    RtScene rm(moved, "bvh", 2, &cache);
    RtScene rl(area, "bvh", 2, &cache);
    RtScene r2(a, "bvh2", 2, &cache);
    EXPECT_EQ(cache.builds(), 4);
    EXPECT_NE(&ra.accel(), &rm.accel());
    EXPECT_NE(&ra.accel(), &rl.accel());
    EXPECT_NE(&ra.accel(), &r2.accel());
    // Each answers for its own shapes: the smaller sphere is missed where the first is met.
    EXPECT_NE(ra.geometry().shapes[1].radius, rm.geometry().shapes[1].radius);
}

TEST(AccelCache, KeepsTheMostRecentlyUsedEntries) {
    AccelCache cache(1);
    const Scene a = spheres();
    const Scene b = spheres({{"objects.1.radius", "0.25"}});
    { RtScene r(a, "bvh", 2, &cache); }
    { RtScene r(a, "bvh", 2, &cache); }  // a hit
    EXPECT_EQ(cache.builds(), 1);
    { RtScene r(b, "bvh", 2, &cache); }  // evicts a's
    { RtScene r(a, "bvh", 2, &cache); }
    EXPECT_EQ(cache.builds(), 3);
}

TEST(AccelCache, AFailedBuildLeavesNothingBehind) {
    AccelCache cache;
    const Scene a = spheres();
    EXPECT_THROW({ RtScene r(a, "no-such-structure", 2, &cache); }, Error);
    EXPECT_EQ(cache.builds(), 0);
    RtScene r(a, "bvh", 2, &cache);
    EXPECT_EQ(cache.builds(), 1);
}

TEST(AccelCache, ASharedStructureRendersTheSameImage) {
    // Whitted builds the structure on two threads; the path tracer, on one, reuses it.
    AccelCache cache;
    const Scene whitted = spheres({{"render.engine", "\"whitted\""}});
    const Scene path = spheres({{"render.engine", "\"path\""}, {"render.spp", "4"}});
    RenderOptions shared;
    shared.accels = &cache;
    shared.threads = 2;
    WhittedRenderer().render(whitted, shared);
    shared.threads = 1;
    const RenderResult with = PathRenderer().render(path, shared);
    EXPECT_EQ(cache.builds(), 1);
    RenderOptions own;
    own.threads = 1;
    const RenderResult without = PathRenderer().render(path, own);
    ASSERT_EQ(with.color.pixels.size(), without.color.pixels.size());
    for (size_t k = 0; k < with.color.pixels.size(); ++k)
        ASSERT_EQ(with.color.pixels[k], without.color.pixels[k]) << "pixel " << k;
}

}  // namespace
}  // namespace svetlo
