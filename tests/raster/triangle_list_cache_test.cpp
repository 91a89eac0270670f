// The rasterizer's triangle list and its raytraced shadows' BVH, built once for the renders of
// one command (geometry/triangle_list_cache.h, docs/compare.md "One scene, one BVH"): frames
// of a drag share them, and each image is bit for bit the one rendered without the caches;
// what changes the list (a shape, the tessellation, Gouraud's split vertices, shadow volumes'
// adjacency) builds its own.
#include "svetlo/geometry/triangle_list_cache.h"

#include <gtest/gtest.h>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/occluder_cube.h"
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
    OccluderCubeCache cubes;
};

RenderResult render(const Scene& scene, Caches* caches, int threads = 2) {
    RenderOptions options;
    options.threads = threads;
    if (caches) {
        options.triangle_lists = &caches->lists;
        options.accels = &caches->accels;
        options.occluder_cubes = &caches->cubes;
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

// The raytraced shadows' occluder cubes (geometry/occluder_cube.h) are kept by the light's
// point as well as the list: a moved light gets its own, a moved camera reuses them, and every
// frame is the frame rendered without them, bit for bit.
TEST(TriangleListCache, TheOccluderCubesFollowTheLights) {
    Caches caches;
    // The viewer's preview: each light with area from its centre, two point casters.
    const std::vector<Override> preview = {{"render.area_light_points", "1"},
                                           {"render.area_shadow_points", "1"}};
    auto with = [&](std::vector<Override> o) {
        o.insert(o.end(), preview.begin(), preview.end());
        return raster_scene(o);
    };
    const Scene frames[] = {
        with({}),
        with({{"camera.position", "[2, 2.2, 6]"}}),   // the camera moved: no new cube
        with({{"lights.0.position", "[-1, 3, 2]"}}),  // the point light moved: one
        with({{"lights.0.position", "[-1, 3, 2]"}, {"camera.position", "[-3, 3, 5]"}}),
        with({}),  // back: both kept
    };
    const int builds[] = {2, 2, 3, 3, 3};
    for (size_t k = 0; k < std::size(frames); ++k) {
        expect_same_pixels(render(frames[k], &caches).color, render(frames[k], nullptr).color);
        EXPECT_EQ(caches.cubes.builds(), builds[k]) << "frame " << k;
    }
}

// The viewer keeps its renderers from one request to the next (src/svetlo/job/renderer_pool.h),
// so that a frame draws into the last one's buffers: each frame of one renderer, whatever
// came before it (another scene, size, shadow technique or texture, a frame that threw), is
// the frame of a new renderer, bit for bit.
TEST(RasterRenderer, OneRendererDrawsEachFrameAsANewOneWould) {
    RasterRenderer kept;
    RenderOptions options;
    options.threads = 2;
    // Another texture for the floor (float texels, a checker), so that the kept mip chains
    // must be made again.
    Image checker(16, 16);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) checker.at(i, j) = Color((i / 4 + j / 4) % 2 ? 0.9f : 0.1f);
    const std::string texture = testing::TempDir() + "/svetlo_kept_checker.pfm";
    write_image(texture, checker, PixelMeaning::Data, 1.0f, "the test's texture");
    // Two environment maps (a bright spot on a gradient, in two places), so that the kept
    // image-based lighting must be made again when the map, its rotation or its scale change.
    std::string maps[2];
    for (int m = 0; m < 2; ++m) {
        Image sky(32, 16);
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 32; ++i)
                sky.at(i, j) = Color(0.2f + 0.05f * j, 0.3f, 0.4f) *
                               ((i == 8 + 12 * m && j == 4) ? 200.0f : 1.0f);
        maps[m] = testing::TempDir() + "/svetlo_kept_sky" + std::to_string(m) + ".pfm";
        write_image(maps[m], sky, PixelMeaning::Radiance, 1.0f, "the test's map");
    }
    const auto sky = [&](int m, const char* rest) {
        return raster_scene({{"environment", "{\"file\": \"" + maps[m] + "\"" + rest + "}"}});
    };
    const Scene frames[] = {
        raster_scene(),
        sky(0, ""),
        sky(0, ", \"rotate\": 90"),
        sky(0, ", \"rotate\": 90, \"scale\": 2"),
        sky(1, ", \"rotate\": 90, \"scale\": 2"),
        sky(0, ""),
        load_scene(SVETLO_SCENES "/shadows.json",
                   {{"film.width", "64"}, {"film.height", "40"}, {"render.spp", "4"}}),
        raster_scene({{"render.shadows", "\"volume\""}, {"film.width", "20"}}),
        raster_scene({{"render.shadows", "\"map\""}, {"camera.position", "[2, 2.2, 6]"}}),
        raster_scene({{"materials.floor.albedo.texture", "\"" + texture + "\""}}),
        raster_scene(),
    };
    for (const Scene& scene : frames)
        expect_same_pixels(kept.render(scene, options).color,
                           RasterRenderer().render(scene, options).color);
    // A frame that throws after taking the buffers (the stencil masks would not fit), then
    // the frames again.
    const Scene too_large = raster_scene({{"render.shadows", "\"volume\""},
                                          {"film.width", "1920"},
                                          {"film.height", "1080"},
                                          {"render.spp", "64"},
                                          {"render.area_shadow_points", "64"}});
    EXPECT_THROW(kept.render(too_large, options), Error);
    for (const Scene& scene : frames)
        expect_same_pixels(kept.render(scene, options).color,
                           RasterRenderer().render(scene, options).color);
}

}  // namespace
}  // namespace svetlo
