// The rasterizer against the ray tracer: the same scene through both engines gives the same
// image, up to the tessellation of curved shapes, and the same coverage.
#include <gtest/gtest.h>

#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"
#include "svetlo/scene/scene_loader.h"
#include "test_scenes.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

RenderResult render(const json& j, const std::string& engine, std::vector<std::string> aovs) {
    Scene scene = scene_from_json(j, "test.json");
    RenderOptions options;
    options.threads = 2;
    options.aovs = std::move(aovs);
    if (engine == "whitted") return WhittedRenderer().render(scene, options);
    return RasterRenderer().render(scene, options);
}

using test_scenes::floor_quad;

TEST(RasterAgainstWhitted, PhongShadedSphereMatchesTheRayTracer) {
    json j = {
        {"camera", {{"position", {0, 0.5, 4}}, {"look_at", {0, 0, 0}}, {"fov", 35}}},
        {"film", {{"width", 96}, {"height", 96}}},
        {"render", {{"spp", 1}, {"max_depth", 0}, {"ambient", 0.05}}},
        {"materials",
         {{"m",
           {{"type", "blinn_phong"}, {"kd", 0.6}, {"ks", 0.3}, {"shininess", 30}, {"ka", 1}}}}},
        {"lights", {{{"type", "point"}, {"position", {2, 3, 3}}, {"intensity", 20}}}},
        {"objects",
         {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}}}}};
    RenderResult ras = render(j, "raster", {"depth"});
    RenderResult ray = render(j, "whitted", {"depth"});
    const Image& dr = ras.aovs.at("depth");
    const Image& dt = ray.aovs.at("depth");
    // Differences relative to the brightest pixel (relative ones explode at the terminator).
    float peak = 0.0f;
    for (const Color& c : ray.color.pixels) peak = std::max(peak, luminance(c));
    double sum = 0.0;
    int n = 0;
    float worst = 0.0f;
    for (int y = 1; y < 95; ++y) {
        for (int x = 1; x < 95; ++x) {
            bool inside = true;  // the pixel and its neighbours are on the sphere in both
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    inside = inside && dr.at(x + dx, y + dy).r > 0 && dt.at(x + dx, y + dy).r > 0;
            if (!inside) continue;
            float rel =
                std::abs(luminance(ras.color.at(x, y)) - luminance(ray.color.at(x, y))) / peak;
            worst = std::max(worst, rel);
            sum += rel;
            ++n;
        }
    }
    ASSERT_GT(n, 3000);
    EXPECT_LT(sum / n, 0.005);  // 0.5 % of the peak on average
    EXPECT_LT(worst, 0.02f);    // 2 % at worst (the default 64 x 32 tessellation)
}
TEST(RasterAgainstWhitted, NearPlaneClippingMatchesTheRayTracersCoverage) {
    // A camera close to a floor that extends far behind it: triangles cross the camera plane.
    json j = {
        {"camera", {{"position", {0, 0.3, 0}}, {"look_at", {0, 0.1, -1}}, {"fov", 70}}},
        {"film", {{"width", 64}, {"height", 48}}},
        {"render", {{"spp", 1}, {"max_depth", 0}}},
        {"materials", {{"m", {{"type", "lambert"}, {"albedo", 0.5}}}}},
        {"lights", {{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 1}}}},
        {"objects",
         {floor_quad(20.0f, "m"),
          {{"type", "box"}, {"min", {-0.5, 0, -2}}, {"max", {0.5, 0.6, 0.5}}, {"material", "m"}}}}};
    RenderResult ras = render(j, "raster", {"depth"});
    RenderResult ray = render(j, "whitted", {"depth"});
    const Image& a = ras.aovs.at("depth");
    const Image& b = ray.aovs.at("depth");
    int covered = 0;
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 64; ++x) {
            bool hit_a = a.at(x, y).r > 0.0f, hit_b = b.at(x, y).r > 0.0f;
            covered += hit_b;
            ASSERT_EQ(hit_a, hit_b) << x << "," << y;
            if (hit_b) {
                ASSERT_NEAR(a.at(x, y).r, b.at(x, y).r, 2e-3f * b.at(x, y).r) << x << "," << y;
            }
        }
    }
    EXPECT_GT(covered, 1000);
}
/// A floor seen from straight above, under an emissive sphere or the same sphere made by CSG.
json glowing_sphere_over_floor(bool csg) {
    json sphere = {{"type", "sphere"}, {"center", {0, 2, 0}}, {"radius", 0.5}};
    json glow = csg ? json{{"type", "csg"}, {"op", "union"}, {"children", {sphere}}} : sphere;
    glow["material"] = "glow";
    return {{"camera",
             {{"position", {0, 1.2, 0}}, {"look_at", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fov", 30}}},
            {"film", {{"width", 9}, {"height", 9}}},
            {"render", {{"spp", 1}, {"max_depth", 0}, {"light_samples", 256}}},
            {"materials",
             {{"white", {{"type", "lambert"}, {"albedo", 0.6}}},
              {"glow", {{"type", "emissive"}, {"radiance", 5}}}}},
            {"objects", {floor_quad(4.0f, "white"), glow}}};
}

TEST(RasterAgainstWhitted, AnEmissiveSphereLightsTheFloorAlikeAndACsgOneInNeither) {
    // Below the sphere's centre at height d: E = pi L (R / d)^2, and L_floor = albedo / pi E.
    const float expected = 0.6f * 5.0f * 0.25f / 4.0f;
    for (const char* engine : {"raster", "whitted"}) {
        RenderResult lit = render(glowing_sphere_over_floor(false), engine, {});
        EXPECT_NEAR(lit.color.at(4, 4).r, expected, 0.03f * expected) << engine;
        RenderResult csg = render(glowing_sphere_over_floor(true), engine, {});
        EXPECT_EQ(csg.color.at(4, 4).r, 0.0f) << engine;
    }
}

TEST(RasterAgainstWhitted, AnObjectAMillionUnitsAwayClipsNothingNear) {
    // A far object used to push the near plane to 10 units (far / 10^5): the sphere 4 units
    // away vanished. The near plane now depends on what is near; the far plane is infinite.
    json j = {
        {"camera", {{"position", {0, 0, 5}}, {"look_at", {0, 0, 0}}, {"fov", 30}}},
        {"film", {{"width", 32}, {"height", 32}}},
        {"render", {{"spp", 1}, {"max_depth", 0}}},
        {"materials", {{"m", {{"type", "lambert"}, {"albedo", 0.5}}}}},
        {"lights", {{{"type", "directional"}, {"direction", {0, 0, -1}}, {"irradiance", 1}}}},
        {"objects",
         {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}},
          {{"type", "sphere"}, {"center", {0, 0, -1e6}}, {"radius", 1000}, {"material", "m"}}}}};
    RenderResult ras = render(j, "raster", {"depth"});
    RenderResult ray = render(j, "whitted", {"depth"});
    // The near sphere at the centre: depth 4, L = 0.5 / pi; and the far one around it.
    EXPECT_NEAR(ras.aovs.at("depth").at(16, 16).r, 4.0f, 1e-2f);  // tessellated: within 0.01
    EXPECT_NEAR(ras.color.at(16, 16).r, ray.color.at(16, 16).r, 1e-3f);
    EXPECT_NEAR(ras.color.at(16, 16).r, 0.5f / kPi, 1e-3f);
}

}  // namespace
}  // namespace svetlo
