// Known-answer scenes for the Whitted engine: every expected value is a closed form computed
// here, independently of the renderer.
#include "svetlo/rt/whitted.h"

#include <gtest/gtest.h>

#include "svetlo/scene/scene_loader.h"
#include "test_scenes.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

RenderResult render(const json& j, std::vector<std::string> aovs = {}, int threads = 2) {
    Scene scene = scene_from_json(j, "test.json");
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return WhittedRenderer().render(scene, options);
}

/// An orthographic camera looking straight down at the square [-half, half]^2 of the y = 0
/// plane; pixel (i, j) centres map to x = -half + (i + 0.5) 2 half / n, z likewise (up = -z).
json top_down(int n, float half) {
    return {{"camera",
             {{"type", "orthographic"},
              {"position", {0, 10, 0}},
              {"look_at", {0, 0, 0}},
              {"up", {0, 0, -1}},
              {"height", 2 * half}}},
            {"film", {{"width", n}, {"height", n}}},
            {"render", {{"engine", "whitted"}, {"spp", 1}, {"max_depth", 0}}}};
}

vec3 pixel_point(int i, int j, int n, float half) {
    float s = 2.0f * half / n;
    return vec3(-half + (i + 0.5f) * s, 0.0f, -half + (j + 0.5f) * s);
}

using test_scenes::floor_quad;

TEST(Whitted, LambertQuadUnderPointLightPerPixel) {
    const int n = 32;
    const float half = 2.0f;
    json j = top_down(n, half);
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.6}}}};
    j["lights"] = {{{"type", "point"}, {"position", {0.3, 1.5, -0.2}}, {"intensity", {8, 4, 2}}}};
    j["objects"] = {floor_quad(half, "white")};
    RenderResult r = render(j);
    for (int jj = 0; jj < n; ++jj) {
        for (int i = 0; i < n; ++i) {
            vec3 p = pixel_point(i, jj, n, half);
            vec3 d = vec3(0.3f, 1.5f, -0.2f) - p;
            float d2 = glm::dot(d, d), cos_t = d.y / std::sqrt(d2);
            float expected = 0.6f / kPi * 8.0f * cos_t / d2;  // albedo/pi * I cos / d^2
            ASSERT_NEAR(r.color.at(i, jj).r, expected, 1e-5f * expected) << i << "," << jj;
            ASSERT_NEAR(r.color.at(i, jj).b, expected / 4.0f, 1e-5f * expected);
        }
    }
}

TEST(Whitted, PhongAndBlinnPhongUnderDirectionalLight) {
    const int n = 8;
    for (bool blinn : {false, true}) {
        json j = top_down(n, 1.0f);
        j["materials"] = {{"shiny",
                           {{"type", blinn ? "blinn_phong" : "phong"},
                            {"kd", 0.4},
                            {"ks", 0.5},
                            {"shininess", 8},
                            {"ka", 0.25}}}};
        vec3 travel = glm::normalize(vec3(0.3f, -1.0f, 0.1f));
        j["lights"] = {{{"type", "directional"},
                        {"direction", {travel.x, travel.y, travel.z}},
                        {"irradiance", 2.0}}};
        j["render"]["ambient"] = 0.1;
        j["objects"] = {floor_quad(1.0f, "shiny")};
        RenderResult r = render(j);
        vec3 nrm(0, 1, 0), l = -travel, v(0, 1, 0);  // orthographic: the eye is straight up
        float cos_t = l.y;
        float spec =
            blinn ? 16.0f / (8.0f * kPi) * std::pow(glm::normalize(l + v).y, 8.0f)
                  : 10.0f / (2.0f * kPi) * std::pow(glm::dot(2.0f * cos_t * nrm - l, v), 8.0f);
        float expected = 0.25f * 0.1f + (0.4f / kPi + 0.5f * spec) * 2.0f * cos_t;
        for (const Color& c : r.color.pixels) ASSERT_NEAR(c.g, expected, 1e-5f * expected) << blinn;
    }
}

TEST(Whitted, FresnelThroughASlabAtNormalIncidence) {
    // An emitter of radiance 1 seen through a glass slab (n = 1.5) at normal incidence: the
    // transmitted series (1 - R)^2 (1 + R^2 + R^4 ...) sums to (1 - R) / (1 + R), R = 0.04.
    json j = {
        {"camera",
         {{"type", "orthographic"},
          {"position", {0, 0, 5}},
          {"look_at", {0, 0, 0}},
          {"height", 1}}},
        {"film", {{"width", 4}, {"height", 4}}},
        {"render", {{"max_depth", 30}}},
        {"materials",
         {{"glass", {{"type", "dielectric"}, {"ior", 1.5}}},
          {"light", {{"type", "emissive"}, {"radiance", 1}}}}},
        {"objects",
         {{{"type", "box"}, {"min", {-5, -5, 0}}, {"max", {5, 5, 0.5}}, {"material", "glass"}},
          {{"type", "quad"},
           {"corner", {-5, -5, -2}},
           {"edge_u", {10, 0, 0}},
           {"edge_v", {0, 10, 0}},
           {"material", "light"}}}}};
    RenderResult r = render(j);
    const float R = 0.04f;
    for (const Color& c : r.color.pixels) EXPECT_NEAR(c.r, (1 - R) / (1 + R), 2e-5f);
    // Without the interreflections (max_depth 2: in, out) it is (1 - R)^2.
    j["render"]["max_depth"] = 2;
    RenderResult once = render(j);
    EXPECT_NEAR(once.color.pixels[0].r, (1 - R) * (1 - R), 2e-5f);
}

TEST(Whitted, MirrorReflectsAnEmitterAndEmittersAreOneSided) {
    json j = {{"camera",
               {{"type", "orthographic"},
                {"position", {0, 0, 5}},
                {"look_at", {0, 0, 0}},
                {"height", 1}}},
              {"film", {{"width", 4}, {"height", 4}}},
              {"render", {{"max_depth", 1}}},
              {"materials",
               {{"mirror", {{"type", "mirror"}, {"reflectance", {0.7, 0.5, 0.3}}}},
                {"light", {{"type", "emissive"}, {"radiance", 2}}}}},
              // The emitter faces -z (toward the mirror), behind the camera's near side.
              {"objects",
               {{{"type", "quad"},
                 {"corner", {-5, -5, 0}},
                 {"edge_u", {10, 0, 0}},
                 {"edge_v", {0, 10, 0}},
                 {"material", "mirror"}},
                {{"type", "quad"},
                 {"corner", {-5, -5, 8}},
                 {"edge_u", {0, 10, 0}},
                 {"edge_v", {10, 0, 0}},
                 {"material", "light"}}}}};
    RenderResult r = render(j);
    EXPECT_NEAR(r.color.pixels[5].r, 1.4f, 1e-6f);
    EXPECT_NEAR(r.color.pixels[5].b, 0.6f, 1e-6f);
    // Flip the emitter: the mirror now sees its back, which emits nothing.
    j["objects"][1]["edge_u"] = {10, 0, 0};
    j["objects"][1]["edge_v"] = {0, 10, 0};
    EXPECT_EQ(render(j).color.pixels[5], Color(0.0f));
}

TEST(Whitted, HardShadowOfASphereMatchesTheExactShadow) {
    const int n = 64;
    const float half = 3.0f;
    json j = top_down(n, half);
    vec3 light(1.5f, 3.0f, 0.5f), centre(0.0f, 1.0f, 0.0f);
    const float radius = 0.6f;
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}};
    j["lights"] = {
        {{"type", "point"}, {"position", {light.x, light.y, light.z}}, {"intensity", 10}}};
    j["objects"] = {
        floor_quad(half, "white"),
        {{"type", "sphere"}, {"center", {0, 1, 0}}, {"radius", radius}, {"material", "white"}}};
    // The camera sees the floor except where the sphere hides it (depth < 10).
    RenderResult r = render(j, {"visibility", "depth"});
    const Image& vis = r.aovs.at("visibility");
    const Image& depth = r.aovs.at("depth");
    int checked = 0, shadowed = 0;
    float s = 2.0f * half / n;
    for (int jj = 0; jj < n; ++jj) {
        for (int i = 0; i < n; ++i) {
            vec3 p = pixel_point(i, jj, n, half);
            // The ray reaches the floor unless the sphere is in the way (depth < 10).
            if (std::abs(depth.at(i, jj).r - 10.0f) > 1e-3f) continue;
            // Exact: p is shadowed iff the segment p -> light passes within `radius` of the
            // centre. Skip pixels whose footprint straddles the shadow's edge.
            vec3 d = glm::normalize(light - p);
            float along = glm::dot(centre - p, d);
            float miss = glm::length(centre - p - along * d);
            float slack = s * 1.5f;
            if (std::abs(miss - radius) < slack) continue;
            bool exact = miss < radius;
            ASSERT_EQ(vis.at(i, jj).r, exact ? 0.0f : 1.0f) << i << "," << jj;
            if (exact) {
                EXPECT_EQ(r.color.at(i, jj), Color(0.0f));
                ++shadowed;
            }
            ++checked;
        }
    }
    EXPECT_GT(shadowed, 50);
    EXPECT_GT(checked, 2000);
}

TEST(Whitted, SpotLightCones) {
    const int n = 48;
    const float half = 3.0f;
    json j = top_down(n, half);
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 1.0}}}};
    j["lights"] = {{{"type", "spot"},
                    {"position", {0, 2, 0}},
                    {"direction", {0, -1, 0}},
                    {"intensity", 5},
                    {"inner_angle", 20},
                    {"outer_angle", 40}}};
    j["objects"] = {floor_quad(half, "white")};
    RenderResult r = render(j);
    float ci = std::cos(radians(20.0f)), co = std::cos(radians(40.0f));
    int inside = 0, penumbra = 0, outside = 0;
    for (int jj = 0; jj < n; ++jj) {
        for (int i = 0; i < n; ++i) {
            vec3 p = pixel_point(i, jj, n, half);
            vec3 d = p - vec3(0, 2, 0);
            float d2 = glm::dot(d, d), c = -d.y / std::sqrt(d2);
            float t = std::clamp((c - co) / (ci - co), 0.0f, 1.0f);
            float factor = t * t * (3 - 2 * t);
            float expected = 1.0f / kPi * 5.0f * factor * c / d2;
            // Relative 1e-4: the smoothstep of a cosine difference amplifies float rounding.
            ASSERT_NEAR(r.color.at(i, jj).r, expected, 1e-4f * std::max(expected, 1e-3f));
            (factor == 1.0f ? inside : factor == 0.0f ? outside : penumbra)++;
        }
    }
    EXPECT_GT(inside, 50);
    EXPECT_GT(penumbra, 50);
    EXPECT_GT(outside, 50);
}

TEST(Whitted, SoftShadowVisibilityIsTheVisibleFractionOfTheLight) {
    // A square area light [-1, 1]^2 at height 2 facing down; an opaque plate at height 1 covers
    // x < 0. From a floor point (x0, 0, z), the ray to (xl, 2, zl) crosses y = 1 at
    // x = (x0 + xl) / 2, so it is blocked when xl < -x0: visible fraction (1 + clamp(x0))/2.
    const int n = 16;
    const float half = 1.5f;
    json j = top_down(n, half);
    j["camera"]["position"] = {0, 0.5, 0};  // between floor and plate
    j["render"]["light_samples"] = 1024;
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}};
    j["lights"] = {{{"type", "area"},
                    {"corner", {-1, 2, -1}},
                    {"edge_u", {2, 0, 0}},
                    {"edge_v", {0, 0, 2}},
                    {"radiance", 1}}};
    j["objects"] = {floor_quad(half, "white"),
                    {{"type", "quad"},
                     {"corner", {-10, 1, -10}},
                     {"edge_u", {10, 0, 0}},
                     {"edge_v", {0, 0, 20}},
                     {"material", "white"}}};
    RenderResult r = render(j, {"visibility"});
    const Image& vis = r.aovs.at("visibility");
    double max_error = 0.0;
    for (int jj = 0; jj < n; ++jj) {
        for (int i = 0; i < n; ++i) {
            float x0 = pixel_point(i, jj, n, half).x;
            float expected = 0.5f * (1.0f + std::clamp(x0, -1.0f, 1.0f));
            max_error =
                std::max(max_error, static_cast<double>(std::abs(vis.at(i, jj).r - expected)));
        }
    }
    // 32 x 32 stratified samples: one column of 32 strata straddles the shadow's edge, so
    // the error's standard deviation is at most sqrt(32 / 4) / 1024 = 0.003.
    EXPECT_LT(max_error, 0.015);
}

TEST(Whitted, AreaLightIrradianceMatchesTheDiskLikeClosedForm) {
    // Irradiance under the centre of a square light of side 2a at height h (Lambert's form
    // factor of a parallel rectangle): E = L * 4 [ a/sqrt(a^2+h^2) atan(a/sqrt(a^2+h^2)) ].
    json j = top_down(1, 0.001f);
    j["render"]["light_samples"] = 4096;
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 1.0}}}};
    j["lights"] = {{{"type", "area"},
                    {"corner", {-1, 1, -1}},
                    {"edge_u", {2, 0, 0}},
                    {"edge_v", {0, 0, 2}},
                    {"radiance", 3}}};
    j["objects"] = {floor_quad(5.0f, "white")};
    j["camera"]["position"] = {0, 0.5, 0};
    RenderResult r = render(j);
    float a = 1.0f, h = 1.0f, s = std::sqrt(a * a + h * h);
    float E = 3.0f * 4.0f * (a / s) * std::atan(a / s);
    EXPECT_NEAR(r.color.pixels[0].r, E / kPi, 0.01f * E / kPi);
}

TEST(Whitted, SameImageWhateverTheThreadCount) {
    json j = top_down(40, 2.0f);
    j["render"]["spp"] = 4;
    j["render"]["max_depth"] = 4;
    j["render"]["light_samples"] = 2;
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.5}}},
                      {"glass", {{"type", "dielectric"}, {"ior", 1.5}}}};
    j["lights"] = {{{"type", "area"},
                    {"corner", {-1, 3, -1}},
                    {"edge_u", {2, 0, 0}},
                    {"edge_v", {0, 0, 2}},
                    {"radiance", 2}}};
    j["objects"] = {
        floor_quad(2.0f, "white"),
        {{"type", "sphere"}, {"center", {0, 1, 0}}, {"radius", 0.7}, {"material", "glass"}}};
    RenderResult one = render(j, {"visibility"}, 1), two = render(j, {"visibility"}, 2);
    ASSERT_EQ(one.color.pixels.size(), two.color.pixels.size());
    EXPECT_EQ(0, std::memcmp(one.color.pixels.data(), two.color.pixels.data(),
                             one.color.pixels.size() * sizeof(Color)));
    EXPECT_EQ(
        0, std::memcmp(one.aovs["visibility"].pixels.data(), two.aovs["visibility"].pixels.data(),
                       one.color.pixels.size() * sizeof(Color)));
    // Asking for AOVs does not change the image.
    RenderResult plain = render(j, {}, 2);
    EXPECT_EQ(0, std::memcmp(one.color.pixels.data(), plain.color.pixels.data(),
                             one.color.pixels.size() * sizeof(Color)));
}

TEST(Whitted, EmitterSeenDirectlyShowsItsRadianceAndBackgroundFillsMisses) {
    json j = top_down(4, 1.0f);
    j["render"]["background"] = {0.1, 0.2, 0.3};
    j["materials"] = {{"glow", {{"type", "emissive"}, {"radiance", {1, 2, 3}}}}};
    j["objects"] = {
        {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.5}, {"material", "glow"}}};
    RenderResult r = render(j);
    EXPECT_EQ(r.color.at(2, 2), Color(1, 2, 3));
    EXPECT_EQ(r.color.at(0, 0), Color(0.1f, 0.2f, 0.3f));
}

}  // namespace
}  // namespace svetlo
