// The rasterizer's triangle list and its raytraced shadows' BVH, built once for the renders of
// one command (geometry/triangle_list_cache.h, docs/compare.md "One scene, one BVH"): frames
// of a drag share them, and each image is bit for bit the one rendered without the caches;
// what changes the list (a shape, the tessellation, Gouraud's split vertices, shadow volumes'
// adjacency) builds its own.
#include "svetlo/geometry/triangle_list_cache.h"

#include <gtest/gtest.h>

#include "svetlo/geometry/accel_cache.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

/// scenes/raster.json (a tessellated implicit torus, spheres, a box, a cone, an area light and
/// a point light, raytraced shadows) with `overrides`, small.
Scene raster_scene(std::vector<Override> overrides = {}) {
    overrides.insert(overrides.begin(),
                     {{"film.width", "48"}, {"film.height", "30"}, {"render.spp", "1"}});
    return load_scene(SVETLO_SCENES "/raster.json", overrides);
}

struct Caches {
    TriangleListCache lists;
    AccelCache accels;
};

RenderResult render(const Scene& scene, Caches* caches, int threads = 2) {
    RenderOptions options;
    options.threads = threads;
    if (caches) {
        options.triangle_lists = &caches->lists;
        options.accels = &caches->accels;
    }
    return RasterRenderer().render(scene, options);
}

void expect_same_pixels(const Image& a, const Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    for (size_t k = 0; k < a.pixels.size(); ++k) ASSERT_EQ(a.pixels[k], b.pixels[k]) << k;
}

TEST(TriangleListCache, TheFramesOfADragShareTheListAndTheShadowBvh) {
    Caches caches;
    const Scene frames[] = {raster_scene(), raster_scene({{"camera.position", "[2, 2.2, 6]"}}),
                            raster_scene({{"camera.position", "[-3, 3, 5]"}})};
    for (const Scene& scene : frames) {
        EXPECT_EQ(scene.geometry_key, frames[0].geometry_key);
        // One thread without the caches, two with them: the same pixels.
        expect_same_pixels(render(scene, &caches).color, render(scene, nullptr, 1).color);
    }
    EXPECT_EQ(caches.lists.builds(), 1);
    EXPECT_EQ(caches.accels.builds(), 1);  // the raytraced shadows' BVH
}

TEST(TriangleListCache, WhatChangesTheListBuildsItsOwn) {
    Caches caches;
    render(raster_scene(), &caches);
    // Shadow maps draw the same list as raytraced shadows, and build no BVH.
    render(raster_scene({{"render.shadows", "\"map\""}}), &caches);
    EXPECT_EQ(caches.lists.builds(), 1);
    EXPECT_EQ(caches.accels.builds(), 1);
    const std::vector<std::vector<Override>> others = {
        {{"render.tessellation", "24"}},
        {{"render.shading", "\"gouraud\""}},   // vertices split by material
        {{"render.shadows", "\"volume\""}},    // edge adjacency
        {{"objects.1.radius", "0.6"}},         // a shape
        {{"lights.1.corner", "[1, 3.6, -1]"}}  // the area light's quad
    };
    int lists = 1;
    for (const std::vector<Override>& o : others) {
        const Scene scene = raster_scene(o);
        expect_same_pixels(render(scene, &caches).color, render(scene, nullptr).color);
        EXPECT_EQ(caches.lists.builds(), ++lists) << o[0].key;
    }
}

}  // namespace
}  // namespace svetlo
