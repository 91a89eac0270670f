// Alpha (docs/real-scenes.md, "Alpha") in every engine: a masked texel is a hole for camera
// rays and for every shadow technique but shadow volumes (geometric by design); a blend covers
// its fraction of what lies behind. Both windings of the surface with alpha.
#include <gtest/gtest.h>

#include <filesystem>

#include "image_means.h"
#include "render_json.h"
#include "svetlo/core/image_io.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A 2 x 1 coverage map: a hole on the left half (u < 1/2), solid on the right.
std::string half_mask() {
    Image im(2, 1);
    im.at(0, 0) = Color(0.0f);
    im.at(1, 0) = Color(1.0f);
    const fs::path path = fs::temp_directory_path() / "svetlo_alpha_half.pfm";
    write_image(path, im, PixelMeaning::Radiance, 1.0f, "test");
    return path.string();
}

json masked(json material) {
    material["alpha"] = {{"texture", half_mask()}, {"filter", "nearest"}, {"wrap", "clamp"}};
    return material;
}

/// A red glowing square of side 2 at z = 0 (its front toward the camera, or away), masked on
/// its left half, before a blue glowing square at z = -1.
json window(bool front, const char* engine) {
    json corner = front ? json{-1, -1, 0} : json{-1, 1, 0};
    json edge_v = front ? json{0, 2, 0} : json{0, -2, 0};
    return {
        {"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 20}}},
        {"film", {{"width", 16}, {"height", 16}}},
        {"render", {{"engine", engine}, {"spp", 4}, {"max_depth", 2}}},
        {"materials",
         {{"glass_red", masked({{"type", "lambert"}, {"albedo", 0.0}, {"emission", {2, 0, 0}}})},
          {"blue", {{"type", "lambert"}, {"albedo", 0.0}, {"emission", {0, 0, 1}}}}}},
        {"lights", json::array()},
        {"objects",
         {{{"type", "quad"},
           {"corner", corner},
           {"edge_u", {2, 0, 0}},
           {"edge_v", edge_v},
           {"material", "glass_red"}},
          {{"type", "quad"},
           {"corner", {-3, -3, -1}},
           {"edge_u", {6, 0, 0}},
           {"edge_v", {0, 6, 0}},
           {"material", "blue"}}}}};
}

template <class Engine>
void expect_window(const char* engine) {
    for (bool front : {true, false}) {
        const RenderResult r = render_json<Engine>(window(front, engine));
        // Columns 3-6 see the hole (the blue square behind), 9-12 the solid half.
        EXPECT_NEAR(mean(r.color, 3, 4, 7, 12, 2), 1.0, 1e-3) << engine << " hole " << front;
        EXPECT_NEAR(mean(r.color, 3, 4, 7, 12, 0), 0.0, 1e-3) << engine << " hole " << front;
        EXPECT_NEAR(mean(r.color, 9, 4, 13, 12, 0), front ? 2.0 : 0.0, 1e-3)
            << engine << " solid " << front;
        EXPECT_NEAR(mean(r.color, 9, 4, 13, 12, 2), 0.0, 1e-3) << engine << " solid " << front;
    }
}

TEST(Alpha, CameraRaysSeeThroughAMasksHolesInEveryEngine) {
    expect_window<RasterRenderer>("raster");
    expect_window<WhittedRenderer>("whitted");
    expect_window<PathRenderer>("path");
    expect_window<RadiosityRenderer>("radiosity");
}

/// A black occluder of 2 x 2 at height 2, masked on its -x half, over a floor of albedo 0.5
/// lit by a directional light of irradiance pi travelling (1, -1, 0) / sqrt 2: the hole's
/// light falls on the floor at x in [-1, 0], the solid half's shadow at [0, 1]. The camera
/// looks straight down at x in [-0.5, 1.5] (the occluder out of its view).
/// As a quad (an analytic shape) or, `mesh`, as its two triangles with the quad's (u, v): the
/// ray tracers' shadow rays then ask the structure's filtered any-hit query
/// (Cutouts::occluded_solid), the quad the closest-hit loop.
json shadow_scene(bool up, const char* engine, const char* shadows, bool mesh = false) {
    json corner = up ? json{-3, 2, 1} : json{-3, 2, -1};
    json edge_v = up ? json{0, 0, -2} : json{0, 0, 2};
    json occluder = {{"type", "quad"},
                     {"corner", corner},
                     {"edge_u", {2, 0, 0}},
                     {"edge_v", edge_v},
                     {"material", "occluder"}};
    if (mesh) {
        const vec3 c(corner[0], corner[1], corner[2]), v(edge_v[0], edge_v[1], edge_v[2]);
        const vec3 u(2, 0, 0);
        json positions = json::array();
        for (const vec3 p : {c, c + u, c + u + v, c + v}) positions.push_back({p.x, p.y, p.z});
        occluder = {{"type", "mesh"},
                    {"positions", positions},
                    {"uvs", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
                    {"indices", {0, 1, 2, 0, 2, 3}},
                    {"material", "occluder"}};
    }
    return {{"camera",
             {{"position", {0.5, 10, 0}},
              {"look_at", {0.5, 0, 0}},
              {"up", {0, 0, -1}},
              {"fov", 2.0 * std::atan(0.1) * 180.0 / kPi}}},
            {"film", {{"width", 32}, {"height", 32}}},
            {"render", {{"engine", engine}, {"spp", 4}, {"max_depth", 1}, {"shadows", shadows}}},
            {"materials",
             {{"occluder", masked({{"type", "lambert"}, {"albedo", 0.0}})},
              {"floor", {{"type", "lambert"}, {"albedo", 0.5}}}}},
            {"lights", {{{"type", "directional"}, {"direction", {1, -1, 0}}, {"irradiance", kPi}}}},
            {"objects",
             {occluder,
              {{"type", "quad"},
               {"corner", {-4, 0, 2}},
               {"edge_u", {8, 0, 0}},
               {"edge_v", {0, 0, -4}},
               {"material", "floor"}}}}};
}

template <class Engine>
void expect_shadow(const char* engine, const char* shadows, bool geometric, double tolerance,
                   bool mesh = false) {
    const double lit = 0.5 * std::sqrt(0.5);  // albedo / pi * pi cos 45
    for (bool up : {true, false}) {
        const RenderResult r = render_json<Engine>(shadow_scene(up, engine, shadows, mesh));
        // Pixel column i sees x = -0.5 + (i + 1/2) / 16: the hole's light at columns 2-6
        // (x in [-0.375, -0.0625]), the shadow at 13-22 (x in [0.3125, 0.9375]).
        EXPECT_NEAR(mean(r.color, 2, 8, 7, 24, 0), geometric ? 0.0 : lit, tolerance)
            << engine << " " << shadows << " through the hole, occluder facing "
            << (up ? "up" : "down");
        EXPECT_NEAR(mean(r.color, 13, 8, 23, 24, 0), 0.0, tolerance)
            << engine << " " << shadows << " under the solid half, " << (up ? "up" : "down");
    }
}

TEST(Alpha, LightPassesAMasksHolesInEveryShadowTechnique) {
    expect_shadow<RasterRenderer>("raster", "map", false, 2e-3);
    expect_shadow<RasterRenderer>("raster", "planar", false, 2e-3);
    expect_shadow<RasterRenderer>("raster", "raytraced", false, 2e-3);
    expect_shadow<RasterRenderer>("raster", "volume", true, 2e-3);  // geometric: no holes
    expect_shadow<WhittedRenderer>("whitted", "raytraced", false, 2e-3);
    expect_shadow<PathRenderer>("path", "raytraced", false, 2e-3);
}

TEST(Alpha, LightPassesAMaskedMeshsHolesInEveryShadowTechnique) {
    expect_shadow<RasterRenderer>("raster", "map", false, 2e-3, true);
    expect_shadow<RasterRenderer>("raster", "planar", false, 2e-3, true);
    expect_shadow<RasterRenderer>("raster", "raytraced", false, 2e-3, true);
    expect_shadow<RasterRenderer>("raster", "volume", true, 2e-3, true);
    expect_shadow<WhittedRenderer>("whitted", "raytraced", false, 2e-3, true);
    expect_shadow<PathRenderer>("path", "raytraced", false, 2e-3, true);
}

TEST(Alpha, RadiositysVisibilitySeesThroughAMasksHoles) {
    // Gathered at each pixel (the direct light's visibility exact), and solved on elements of
    // 1/8 (the light through the hole is the floor's elements' own, to the half element its
    // edges blur: the regions measured keep a whole element away from them).
    for (const char* display : {"gather", "gouraud"}) {
        for (bool up : {true, false}) {
            json scene = shadow_scene(up, "radiosity", "raytraced", !up);  // a mesh facing down
            scene["render"]["radiosity"] = {{"display", display}, {"element_size", 0.125}};
            const RenderResult r = render_json<RadiosityRenderer>(scene);
            const double lit = 0.5 * std::sqrt(0.5);
            EXPECT_NEAR(mean(r.color, 4, 8, 6, 24, 0), lit, 2e-3) << display << " " << up;
            EXPECT_NEAR(mean(r.color, 13, 8, 23, 24, 0), 0.0, 2e-3) << display << " " << up;
        }
    }
}

TEST(Alpha, ABlendCoversItsFractionOfWhatLiesBehind) {
    // Coverage 0.25 everywhere: a quarter of the red square's 2 and three quarters of blue.
    for (const char* engine : {"raster", "path"}) {
        json scene = window(true, engine);
        scene["materials"]["glass_red"]["alpha"] = 0.25;
        scene["materials"]["glass_red"]["alpha_mode"] = "blend";
        scene["render"]["spp"] = 256;
        const RenderResult r = std::string(engine) == "raster" ? render_json<RasterRenderer>(scene)
                                                               : render_json<PathRenderer>(scene);
        EXPECT_NEAR(mean(r.color, 3, 4, 13, 12, 0), 0.5, 0.03) << engine;
        EXPECT_NEAR(mean(r.color, 3, 4, 13, 12, 2), 0.75, 0.03) << engine;
    }
}

/// A floor of albedo 0.5 under a glowing square of side 2 at height 2, facing down: masked on
/// its -x half, or (`half`) only its +x half there, unmasked. The camera looks down at the
/// floor from above the lamp (which it does not see: the floor's view is under it).
json lamp_scene(bool half, const char* engine) {
    json lamp = {{"type", "lambert"}, {"albedo", 0.0}, {"emission", 4.0}};
    json corner = half ? json{0, 2, -1} : json{-1, 2, -1};
    json edge_u = half ? json{1, 0, 0} : json{2, 0, 0};
    return {
        {"camera",
         {{"position", {0, 1.5, 0}}, {"look_at", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fov", 60}}},
        {"film", {{"width", 16}, {"height", 16}}},
        {"render", {{"engine", engine}, {"spp", 256}, {"max_depth", 1}, {"light_samples", 4}}},
        {"materials",
         {{"lamp", half ? lamp : masked(lamp)}, {"floor", {{"type", "lambert"}, {"albedo", 0.5}}}}},
        {"lights", json::array()},
        {"objects",
         {{{"type", "quad"},
           {"corner", corner},
           {"edge_u", edge_u},
           {"edge_v", {0, 0, 2}},
           {"material", "lamp"}},
          {{"type", "quad"},
           {"corner", {-4, 0, 4}},
           {"edge_u", {8, 0, 0}},
           {"edge_v", {0, 0, -8}},
           {"material", "floor"}}}}};
}

TEST(Alpha, AMaskedEmitterLightsWithItsSolidPartAlone) {
    // The light set samples the whole square; its holes emit nothing (and, weighed by the
    // power each triangle emits, are rarely drawn): the floor is lit as by the half alone.
    // (edge_u x edge_v points down: the lamp's front faces the floor.)
    for (const char* engine : {"path", "whitted"}) {
        const bool path = std::string(engine) == "path";
        const RenderResult masked_lamp =
            path ? render_json<PathRenderer>(lamp_scene(false, engine))
                 : render_json<WhittedRenderer>(lamp_scene(false, engine));
        const RenderResult half_lamp = path
                                           ? render_json<PathRenderer>(lamp_scene(true, engine))
                                           : render_json<WhittedRenderer>(lamp_scene(true, engine));
        for (int x0 : {0, 8}) {  // the floor under the hole, then under the solid half
            const double a = mean(masked_lamp.color, x0, 0, x0 + 8, 16, 0);
            const double b = mean(half_lamp.color, x0, 0, x0 + 8, 16, 0);
            EXPECT_GT(b, 0.05) << engine;
            EXPECT_NEAR(a, b, 0.03 * b) << engine << " columns from " << x0;
        }
    }
}

}  // namespace
}  // namespace svetlo
