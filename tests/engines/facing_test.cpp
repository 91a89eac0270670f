// Which side faces the viewer, in every engine and shading mode (shading/shading_frame.h):
// back-face culling keeps what faces the camera, and an emitter shows exactly its radiance
// from the front and nothing from behind.
#include <gtest/gtest.h>

#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

/// The camera at z = 3 looking down -z at a 16 x 16 film; the origin is the centre pixel.
json facing_scene() {
    return {{"camera", {{"position", {0, 0, 3}}, {"look_at", {0, 0, 0}}, {"fov", 40}}},
            {"film", {{"width", 16}, {"height", 16}}},
            {"render", {{"engine", "raster"}, {"spp", 1}, {"max_depth", 0}, {"background", 0}}},
            {"materials", {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}}},
            {"lights", {{{"type", "directional"}, {"direction", {0, 0, -1}}, {"irradiance", 2}}}}};
}

/// A quad across the view, its front (edge_u x edge_v) toward +z (the camera) or -z.
json quad(bool toward_camera, const char* material) {
    json u = {2, 0, 0}, v = {0, 2, 0};
    return {{"type", "quad"},
            {"corner", {-1, -1, 0}},
            {"edge_u", toward_camera ? u : v},
            {"edge_v", toward_camera ? v : u},
            {"material", material}};
}

/// The same square as a mesh of two triangles, counter-clockwise seen from +z or from -z.
json mesh(bool toward_camera, const char* material) {
    json indices = toward_camera ? json{0, 1, 2, 0, 2, 3} : json{0, 2, 1, 0, 3, 2};
    return {{"type", "mesh"},
            {"positions", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}},
            {"indices", indices},
            {"material", material}};
}

Color centre(const json& j, const std::string& engine, int threads = 2) {
    Scene scene = scene_from_json(j, "test.json");
    RenderOptions options;
    options.threads = threads;
    RenderResult r = engine == "whitted" ? WhittedRenderer().render(scene, options)
                                         : RasterRenderer().render(scene, options);
    return r.color.at(8, 8);
}

TEST(Facing, BackFaceCullingKeepsWhatFacesTheCameraForBothWindings) {
    for (bool toward : {true, false}) {
        for (bool is_mesh : {false, true}) {
            for (const char* cull : {"none", "back"}) {
                json j = facing_scene();
                j["render"]["cull"] = cull;
                j["objects"] = {is_mesh ? mesh(toward, "white") : quad(toward, "white")};
                // Lit from behind the camera: E = 2 on either side, L = 0.5 / pi * 2.
                float expected = std::string(cull) == "back" && !toward ? 0.0f : 1.0f / kPi;
                EXPECT_NEAR(centre(j, "raster").g, expected, 1e-5f)
                    << (is_mesh ? "mesh" : "quad") << " toward=" << toward << " cull=" << cull;
            }
        }
    }
}

TEST(Facing, AnEmitterShowsExactlyItsRadianceInEveryModeOfEveryEngine) {
    const Color radiance(3.0f, 2.0f, 0.5f);
    for (bool toward : {true, false}) {
        for (bool is_mesh : {false, true}) {
            json j = facing_scene();
            j["materials"]["glow"] = {{"type", "emissive"}, {"radiance", {3, 2, 0.5}}};
            j["objects"] = {is_mesh ? mesh(toward, "glow") : quad(toward, "glow")};
            // Emission leaves the front side only; the back of an emitter of albedo 0 is black.
            Color expected = toward ? radiance : Color(0.0f);
            struct Variant {
                const char* engine;
                const char* shading;
                int spp;
                const char* antialias;
            };
            for (Variant v :
                 {Variant{"whitted", "phong", 1, "ssaa"}, Variant{"whitted", "phong", 4, "ssaa"},
                  Variant{"raster", "phong", 1, "ssaa"}, Variant{"raster", "phong", 4, "ssaa"},
                  Variant{"raster", "phong", 4, "msaa"}, Variant{"raster", "gouraud", 1, "ssaa"},
                  Variant{"raster", "flat", 1, "ssaa"}, Variant{"raster", "flat", 4, "msaa"}}) {
                j["render"]["shading"] = v.shading;
                j["render"]["spp"] = v.spp;
                j["render"]["antialias"] = v.antialias;
                for (int threads : {1, 2}) {
                    Color c = centre(j, v.engine, threads);
                    for (int k = 0; k < 3; ++k) {
                        EXPECT_NEAR(c[k], expected[k], 1e-6f)
                            << v.engine << " " << v.shading << " spp=" << v.spp << " "
                            << v.antialias << (is_mesh ? " mesh" : " quad") << " toward=" << toward
                            << " threads=" << threads;
                    }
                }
            }
        }
    }
}

TEST(Facing, AnAreaLightSeenDirectlyShowsItsRadianceFromTheFrontOnly) {
    for (bool toward : {true, false}) {
        json j = facing_scene();
        j["lights"] = {{{"type", "area"},
                        {"corner", {-1, -1, 0}},
                        {"edge_u", toward ? json{2, 0, 0} : json{0, 2, 0}},
                        {"edge_v", toward ? json{0, 2, 0} : json{2, 0, 0}},
                        {"radiance", 4}}};
        j["objects"] = json::array();
        for (const char* engine : {"raster", "whitted"}) {
            EXPECT_NEAR(centre(j, engine).r, toward ? 4.0f : 0.0f, 1e-6f)
                << engine << " toward=" << toward;
        }
    }
}

}  // namespace
}  // namespace svetlo
