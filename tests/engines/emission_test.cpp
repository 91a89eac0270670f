// `emission` on any material (docs/scene-format.md, "Keys of every material"): the surface
// shows its emitted radiance from its front side, in every engine, and is a light that lights
// the rest of the scene; seen from behind it emits nothing.
#include <gtest/gtest.h>

#include "image_means.h"
#include "render_json.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

/// A square of side 2 at z = 0 filling the middle of the film, its front toward the camera
/// (at +z) or away; a Lambertian of albedo 0.5 that emits `emission`. No light, black
/// background, no ambient term.
json glowing_square(bool front, const char* engine) {
    json corner = front ? json{-1, -1, 0} : json{-1, 1, 0};
    json edge_v = front ? json{0, 2, 0} : json{0, -2, 0};
    return {{"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 20}}},
            {"film", {{"width", 16}, {"height", 16}}},
            {"render", {{"engine", engine}, {"spp", 4}, {"max_depth", 3}}},
            {"materials",
             {{"glow", {{"type", "lambert"}, {"albedo", 0.5}, {"emission", {2.0, 1.0, 0.5}}}}}},
            {"lights", json::array()},
            {"objects",
             {{{"type", "quad"},
               {"corner", corner},
               {"edge_u", {2, 0, 0}},
               {"edge_v", edge_v},
               {"material", "glow"}}}}};
}

template <class Engine>
void expect_emission(const char* engine) {
    for (bool front : {true, false}) {
        const RenderResult r = render_json<Engine>(glowing_square(front, engine));
        const Color expected = front ? Color(2.0f, 1.0f, 0.5f) : Color(0.0f);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean(r.color, 6, 6, 10, 10, c), expected[c], 1e-4)
                << engine << (front ? " front" : " back") << " channel " << c;
    }
}

TEST(Emission, AnyMaterialShowsItsEmissionFromTheFrontInEveryEngine) {
    expect_emission<RasterRenderer>("raster");
    expect_emission<WhittedRenderer>("whitted");
    expect_emission<PathRenderer>("path");
    expect_emission<RadiosityRenderer>("radiosity");
}

TEST(Emission, AnEmittingLambertianLightsTheFloorAsAnEmissiveQuadDoes) {
    // The same square as a light above a floor, once as `lambert` + `emission`, once as the
    // classic `emissive` material with the same albedo: the path tracer's floor alike.
    auto scene = [](json material) {
        return json{{"camera", {{"position", {0, 3, 4}}, {"look_at", {0, 0, 0}}, {"fov", 40}}},
                    {"film", {{"width", 24}, {"height", 24}}},
                    {"render", {{"engine", "path"}, {"spp", 64}, {"max_depth", 1}}},
                    {"materials", {{"glow", material}, {"floor", {{"type", "lambert"}}}}},
                    {"lights", json::array()},
                    {"objects",
                     {{{"type", "quad"},
                       {"corner", {-0.5, 1, -0.5}},
                       {"edge_u", {1, 0, 0}},
                       {"edge_v", {0, 0, 1}},
                       {"material", "glow"}},
                      {{"type", "quad"},
                       {"corner", {-3, 0, -3}},
                       {"edge_u", {0, 0, 6}},
                       {"edge_v", {6, 0, 0}},
                       {"material", "floor"}}}}};
    };
    const RenderResult a =
        render_json<PathRenderer>(scene({{"type", "lambert"}, {"albedo", 0.0}, {"emission", 4.0}}));
    const RenderResult b =
        render_json<PathRenderer>(scene({{"type", "emissive"}, {"radiance", 4.0}}));
    EXPECT_GT(mean(b.color, 0, 16, 24, 24), 0.05);  // the floor is lit
    EXPECT_EQ(a.color.pixels, b.color.pixels);      // the same light, the same samples
}

}  // namespace
}  // namespace svetlo
