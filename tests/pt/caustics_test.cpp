// Caustics and dispersion in the path tracer: photons through a glass sphere (caustic_photons.h)
// against the path tracer's own unbiased estimate, and white light split into colours.
#include <gtest/gtest.h>

#include "render_json.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/scene/scene_loader.h"
#include "test_scenes.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

RenderResult render(const json& j, int threads = 2) {
    return render_json<PathRenderer>(j, threads);
}

/// A glass sphere of radius 0.5 at height 1.5 over a white floor, lit from above by `light`;
/// an orthographic camera between the sphere and the floor looks down at the square
/// [-0.6, 0.6]^2 of the floor, where the caustic falls.
json glass_sphere(const json& light, const char* caustics, int spp, float abbe = 0.0f) {
    json j = {{"camera",
               {{"type", "orthographic"},
                {"position", {0, 0.5, 0}},
                {"look_at", {0, 0, 0}},
                {"up", {0, 0, -1}},
                {"height", 1.2}}},
              {"film", {{"width", 24}, {"height", 24}}},
              {"render",
               {{"engine", "path"},
                {"spp", spp},
                {"max_depth", 8},
                {"caustics", caustics},
                {"photons", {{"count", 20000}}}}}};
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.8}}},
                      {"glass", {{"type", "dielectric"}, {"ior", 1.5}, {"abbe", abbe}}}};
    j["lights"] = {light};
    j["objects"] = {
        test_scenes::floor_quad(3.0f, "white"),
        {{"type", "sphere"}, {"center", {0, 1.5, 0}}, {"radius", 0.5}, {"material", "glass"}}};
    return j;
}

const json kPointLight = {{"type", "point"}, {"position", {0, 5, 0}}, {"intensity", 10}};

double mean_red(const Image& im, int x0, int y0, int x1, int y1) {
    double s = 0.0;
    for (int j = y0; j < y1; ++j)
        for (int i = x0; i < x1; ++i) s += im.at(i, j).r;
    return s / ((x1 - x0) * (y1 - y0));
}

TEST(Caustics, APointLightThroughGlassFocusesOnTheFloor) {
    // The floor under the sphere lies in its shadow: a path tracer alone finds only the lit
    // floor's light coming back through the glass there, and the photons make a spot
    // brighter than the unshadowed floor would be.
    const double unshadowed = 0.8 / kPi * 10.0 / 25.0;  // albedo / pi * I / d^2
    RenderResult none = render(glass_sphere(kPointLight, "none", 16));
    EXPECT_LT(mean_red(none.color, 10, 10, 14, 14), 0.1 * unshadowed);
    RenderResult lit = render(glass_sphere(kPointLight, "auto", 16));
    EXPECT_GT(mean_red(lit.color, 10, 10, 14, 14), 3.0 * unshadowed);
}

TEST(Caustics, PhotonsAgreeWithThePathTracerUnderAnAreaLight) {
    // From an area light the path tracer finds the caustic itself, unbiased but slowly; with
    // render.caustics = photons it leaves those paths to the photon map. The two means over
    // the caustic agree.
    json area = {{"type", "area"},
                 {"corner", {-0.5, 4, -0.5}},
                 {"edge_u", {1, 0, 0}},
                 {"edge_v", {0, 0, 1}},
                 {"radiance", 10}};  // facing down
    RenderResult paths = render(glass_sphere(area, "none", 2048));
    RenderResult photons = render(glass_sphere(area, "photons", 64));
    double a = mean_red(paths.color, 6, 6, 18, 18), b = mean_red(photons.color, 6, 6, 18, 18);
    EXPECT_GT(a, 0.0);
    EXPECT_NEAR(b, a, 0.05 * a);
}

TEST(Caustics, DispersionSplitsWhiteLightAndWhiteStaysWhiteWithout) {
    RenderResult plain = render(glass_sphere(kPointLight, "auto", 8));
    for (const Color& c : plain.color.pixels) {
        ASSERT_EQ(c.r, c.g);
        ASSERT_EQ(c.g, c.b);
    }
    RenderResult split = render(glass_sphere(kPointLight, "auto", 32, 8.0f));
    // Somewhere the caustic is reddish, somewhere bluish.
    float reddest = 0.0f, bluest = 0.0f;
    for (const Color& c : split.color.pixels) {
        if (c.r + c.b < 0.05f) continue;
        reddest = std::max(reddest, c.r / (c.b + 1e-3f));
        bluest = std::max(bluest, c.b / (c.r + 1e-3f));
    }
    EXPECT_GT(reddest, 1.3f);
    EXPECT_GT(bluest, 1.3f);
}

TEST(Caustics, PhotonsGiveTheSameImageOnOneThreadAndTwo) {
    json j = glass_sphere(kPointLight, "auto", 3, 20.0f);
    RenderResult one = render(j, 1), two = render(j, 2);
    for (size_t k = 0; k < one.color.pixels.size(); ++k)
        ASSERT_EQ(one.color.pixels[k], two.color.pixels[k]) << k;
}

TEST(Caustics, AnyRadiusGivesFinitePixels) {
    // A radius whose grid cells overflow an int, or one that holds the whole scene.
    for (double radius : {1e-30, 1e30}) {
        json j = glass_sphere(kPointLight, "auto", 2);
        j["render"]["photons"]["radius"] = radius;
        RenderResult r = render(j);
        EXPECT_EQ(r.stats.nonfinite, 0u) << radius;
        for (const Color& c : r.color.pixels) ASSERT_TRUE(is_finite(c)) << radius;
    }
}

}  // namespace
}  // namespace svetlo
