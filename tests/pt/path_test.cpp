// Known answers for the path tracer: every expected value is a closed form computed here,
// independently of the renderer, or another engine's answer. Monte Carlo results are compared
// with tolerances of several standard errors, estimated from the render itself where it can.
#include <gtest/gtest.h>

#include "image_means.h"
#include "render_json.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/rt/whitted.h"
#include "svetlo/scene/scene_loader.h"
#include "test_scenes.h"

namespace svetlo {
namespace {

using json = nlohmann::json;
using test_scenes::floor_quad;
using test_scenes::unit_plates;

RenderResult render(const json& j, int threads = 2, std::vector<std::string> aovs = {}) {
    return render_json<PathRenderer>(j, threads, std::move(aovs));
}

/// An orthographic camera at height `y` looking straight down at the square [-half, half]^2
/// of the y = 0 plane (up = -z: pixel rows run along +z).
json top_down(int n, float half, int spp, int max_depth, float y = 10.0f) {
    return {{"camera",
             {{"type", "orthographic"},
              {"position", {0, y, 0}},
              {"look_at", {0, 0, 0}},
              {"up", {0, 0, -1}},
              {"height", 2 * half}}},
            {"film", {{"width", n}, {"height", n}}},
            {"render", {{"engine", "path"}, {"spp", spp}, {"max_depth", max_depth}}}};
}

/// The root-mean-square difference of two images of the same scene with different seeds,
/// divided by sqrt(2): each one's error.
double pair_error(const Image& a, const Image& b) {
    double s = 0.0;
    for (size_t k = 0; k < a.pixels.size(); ++k) {
        Color d = a.pixels[k] - b.pixels[k];
        s += glm::dot(d, d) / 3.0;
    }
    return std::sqrt(s / a.pixels.size() / 2.0);
}

/// The form factor from a differential area to a parallel rectangle a x b at height c, the
/// area's foot at one of its corners (Hottel; Howell's catalogue, configuration B-3).
double corner_form_factor(double a, double b, double c) {
    double x = a / c, y = b / c;
    double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

TEST(Path, WhiteFurnaceShowsTheAlbedo) {
    // A convex diffuse sphere in a uniform environment of radiance 1 reflects only that:
    // L = albedo, at any depth, whatever the mix of light and BSDF samples.
    json j = top_down(16, 1.2f, 64, 64);
    j["render"]["background"] = 1.0;
    j["materials"] = {{"grey", {{"type", "lambert"}, {"albedo", 0.7}}}};
    j["objects"] = {
        {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "grey"}}};
    for (const char* mis : {"power", "light", "bsdf"}) {
        j["render"]["mis"] = mis;
        RenderResult r = render(j);
        EXPECT_NEAR(mean(r.color, 6, 6, 10, 10), 0.7, 0.01) << mis;
        EXPECT_FLOAT_EQ(r.color.at(0, 0).r, 1.0f) << mis;  // the background itself
    }
}

/// The inside of a closed box of six inward-facing emissive quads with radiance le and
/// diffuse albedo rho, seen from its centre.
json emitting_box(double le, double rho, int max_depth) {
    json j = {{"camera", {{"position", {0, 0, 0.5}}, {"look_at", {0, 0, -1}}, {"fov", 60}}},
              {"film", {{"width", 8}, {"height", 8}}},
              {"render", {{"engine", "path"}, {"spp", 64}, {"max_depth", max_depth}}}};
    j["materials"] = {{"glow", {{"type", "emissive"}, {"radiance", le}, {"albedo", rho}}}};
    // Faces of the cube [-1, 1]^3, each with edge_u x edge_v pointing inward.
    json faces = json::array();
    for (int axis = 0; axis < 3; ++axis) {
        for (int side : {-1, 1}) {
            json corner = {-1, -1, -1}, eu = {0, 0, 0}, ev = {0, 0, 0};
            corner[axis] = side;
            int a = (axis + 1) % 3, b = (axis + 2) % 3;
            eu[a] = 2;
            ev[b] = 2;
            // (e_a x e_b) = e_axis: inward at side -1; swap the edges at side +1.
            if (side > 0) std::swap(eu, ev);
            faces.push_back({{"type", "quad"},
                             {"corner", corner},
                             {"edge_u", eu},
                             {"edge_v", ev},
                             {"material", "glow"}});
        }
    }
    j["objects"] = faces;
    return j;
}

TEST(Path, ClosedEmittingBoxGivesEmissionOverOneMinusAlbedo) {
    // L = Le + rho L: L = Le / (1 - rho).
    RenderResult r = render(emitting_box(1.0, 0.5, 200));
    EXPECT_NEAR(mean(r.color), 2.0, 0.03);
    // Depth 0 is Le plus one bounce of direct light: Le (1 + rho).
    RenderResult direct = render(emitting_box(1.0, 0.5, 0));
    EXPECT_NEAR(mean(direct.color), 1.5, 0.02);
}

TEST(Path, DirectLightOfAPointLightMatchesTheClosedForm) {
    // Nothing but a floor: no other surface sends it light, so every depth gives the direct
    // light, albedo / pi * I cos / d^2 (docs/radiometry.md: the common ground of all engines).
    const int n = 16;
    const float half = 2.0f;
    for (int depth : {0, 5}) {
        json j = top_down(n, half, 256, depth);
        j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.6}}}};
        j["lights"] = {{{"type", "point"}, {"position", {0.3, 1.5, -0.2}}, {"intensity", 8}}};
        j["objects"] = {floor_quad(half, "white")};
        RenderResult r = render(j);
        for (int jj = 0; jj < n; jj += 3) {
            for (int i = 0; i < n; i += 3) {
                // The pixel's mean over its area, by a 8 x 8 midpoint rule.
                double expected = 0.0;
                float s = 2 * half / n;
                for (int a = 0; a < 8; ++a) {
                    for (int b = 0; b < 8; ++b) {
                        vec3 p(-half + (i + (a + 0.5f) / 8) * s, 0,
                               -half + (jj + (b + 0.5f) / 8) * s);
                        vec3 d = vec3(0.3f, 1.5f, -0.2f) - p;
                        float d2 = glm::dot(d, d);
                        expected += 0.6 / kPi * 8 * (d.y / std::sqrt(d2)) / d2 / 64;
                    }
                }
                EXPECT_NEAR(r.color.at(i, jj).r, expected, 0.01 * expected) << i << "," << jj;
            }
        }
    }
}

TEST(Path, PointSpotAndDirectionalLightsAtOnceSumTheirClosedForms) {
    // Each vertex samples one light, chosen by power: over the pixels, the mean is the sum of
    // the three closed forms, E = I cos / d^2 (the spot's inner cone covers the floor) and
    // E_dir cos.
    const int n = 16;
    const float half = 1.0f;
    json j = top_down(n, half, 256, 0);
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}};
    j["lights"] = {{{"type", "point"}, {"position", {0.5, 1.5, -0.3}}, {"intensity", 6}},
                   {{"type", "spot"},
                    {"position", {-0.4, 2.0, 0.2}},
                    {"direction", {0, -1, 0}},
                    {"intensity", 20},
                    {"inner_angle", 70},
                    {"outer_angle", 80}},
                   {{"type", "directional"}, {"direction", {0.3, -1, 0.2}}, {"irradiance", 0.7}}};
    j["objects"] = {floor_quad(half, "white")};
    RenderResult r = render(j);
    const vec3 sun = glm::normalize(vec3(-0.3f, 1.0f, -0.2f));
    double expected = 0.0;
    for (int jj = 0; jj < n; ++jj) {
        for (int i = 0; i < n; ++i) {
            float s = 2 * half / n;
            vec3 p(-half + (i + 0.5f) * s, 0, -half + (jj + 0.5f) * s);
            double e = 0.7 * sun.y;
            for (auto [at, intensity] : {std::pair{vec3(0.5f, 1.5f, -0.3f), 6.0f},
                                         std::pair{vec3(-0.4f, 2.0f, 0.2f), 20.0f}}) {
                vec3 d = at - p;
                float d2 = glm::dot(d, d);
                e += intensity * (d.y / std::sqrt(d2)) / d2;
            }
            expected += 0.5 / kPi * e / (n * n);
        }
    }
    EXPECT_NEAR(mean(r.color), expected, 0.01 * expected);
}

TEST(Path, AreaLightAboveAPointMatchesTheFormFactor) {
    // A square area light of side 1 at height 1 above the point under its centre: E = pi L F,
    // F the sum of four corner form factors; L_floor = albedo / pi * E. Every strategy.
    const double F = 4 * corner_form_factor(0.5, 0.5, 1.0);
    json j = top_down(4, 0.01f, 1024, 0, 0.5f);  // under the light
    j["materials"] = {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}};
    j["lights"] = {{{"type", "area"},
                    {"corner", {-0.5, 1, -0.5}},
                    {"edge_u", {1, 0, 0}},
                    {"edge_v", {0, 0, 1}},
                    {"radiance", 2}}};
    j["objects"] = {floor_quad(1.0f, "white")};
    const double expected = 0.5 * 2 * F;
    for (const char* mis : {"power", "light", "bsdf"}) {
        j["render"]["mis"] = mis;
        RenderResult r = render(j);
        EXPECT_NEAR(mean(r.color), expected, 0.01 * expected) << mis;
    }
}

TEST(Path, UnitPlatesThroughRadiometry) {
    for (bool area_light : {true, false}) {
        RenderResult parallel = render(unit_plates(false, area_light));
        EXPECT_NEAR(mean(parallel.color), 0.199825, 0.003) << area_light;
        RenderResult perpendicular = render(unit_plates(true, area_light));
        EXPECT_NEAR(mean(perpendicular.color), 0.200044, 0.003) << area_light;
    }
}

TEST(Path, OrenNayarWithoutRoughnessIsLambert) {
    json j = emitting_box(0.0, 0.0, 3);
    j["lights"] = {{{"type", "point"}, {"position", {0.3, 0.5, -0.2}}, {"intensity", 2}}};
    j["materials"] = {{"glow", {{"type", "lambert"}, {"albedo", 0.6}}}};
    RenderResult lambert = render(j);
    j["materials"] = {{"glow", {{"type", "oren_nayar"}, {"albedo", 0.6}, {"sigma", 0}}}};
    RenderResult oren_nayar = render(j);
    for (size_t k = 0; k < lambert.color.pixels.size(); ++k) {
        EXPECT_NEAR(oren_nayar.color.pixels[k].g, lambert.color.pixels[k].g,
                    1e-5f * lambert.color.pixels[k].g);
    }
}

TEST(Path, NoiseFallsAsOneOverTheRootOfTheSamples) {
    json j = unit_plates(false, true);
    j["render"]["max_depth"] = 2;
    auto error = [&](int spp) {
        j["render"]["spp"] = spp;
        j["render"]["seed"] = 1;
        RenderResult a = render(j);
        j["render"]["seed"] = 2;
        RenderResult b = render(j);
        return pair_error(a.color, b.color);
    };
    // 16 times the samples: a quarter of the error, or less with stratified samples.
    double ratio = error(4) / error(64);
    EXPECT_GT(ratio, 3.5);
}

TEST(Path, AThinLensKeepsThePlaneOfFocusSharpAndBlursTheRest) {
    // A checkered floor seen from 2.83 m: the spread of the pixels around the image's centre
    // (its contrast) through a pinhole, a 0.5 m lens focused on it, and one focused at 10 m,
    // whose circle of confusion there (0.36 m) is wider than a square (0.25 m).
    json j = {{"camera", {{"position", {0, 2, 2}}, {"look_at", {0, 0, 0}}, {"fov", 30}}},
              {"film", {{"width", 32}, {"height", 32}}},
              {"render", {{"engine", "path"}, {"spp", 64}, {"max_depth", 0}}}};
    j["materials"] = {{"board",
                       {{"type", "lambert"},
                        {"albedo", {{"checker", {{"a", 0.9}, {"b", 0.1}, {"scale", 16}}}}}}}};
    j["lights"] = {{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", 3}}};
    j["objects"] = {floor_quad(2.0f, "board")};
    auto contrast = [&]() {
        Image im = render(j).color;
        double m = mean(im, 8, 8, 24, 24), v = 0.0;
        for (int y = 8; y < 24; ++y)
            for (int x = 8; x < 24; ++x) v += (im.at(x, y).r - m) * (im.at(x, y).r - m);
        return std::sqrt(v / 256.0);
    };
    const double pinhole = contrast();
    j["camera"]["aperture"] = 0.5;
    const double focused = contrast();
    j["camera"]["focus_distance"] = 10;
    const double blurred = contrast();
    EXPECT_NEAR(focused, pinhole, 0.1 * pinhole);
    EXPECT_LT(blurred, 0.3 * pinhole);
}

TEST(Path, TheSameImageOnOneThreadAndTwo) {
    json j = emitting_box(1.0, 0.5, 4);
    j["render"]["spp"] = 4;
    j["film"] = {{"width", 24}, {"height", 20}};
    RenderResult one = render(j, 1), two = render(j, 2);
    ASSERT_EQ(one.color.pixels.size(), two.color.pixels.size());
    for (size_t k = 0; k < one.color.pixels.size(); ++k)
        ASSERT_EQ(one.color.pixels[k], two.color.pixels[k]) << k;
}

TEST(Path, ColourBleedsInTheCornellBox) {
    // The white back wall beside the red wall turns red, beside the green wall green: light
    // that the Whitted engine, direct light only, does not carry.
    json j = {{"camera", {{"position", {0, 1, 3.9}}, {"look_at", {0, 1, 0}}, {"fov", 38}}},
              {"film", {{"width", 32}, {"height", 32}}},
              {"render", {{"engine", "path"}, {"spp", 128}, {"max_depth", 8}}},
              {"objects",
               {{{"type", "mesh"}, {"file", SVETLO_SCENE_MODELS "/CornellBox-Original.obj"}}}}};
    RenderResult path = render(j);
    j["render"]["engine"] = "whitted";
    j["render"]["spp"] = 16;
    Scene scene = scene_from_json(j, "test.json");
    RenderResult whitted = WhittedRenderer().render(scene, RenderOptions{});
    // Red against green on the back wall (rows 8-11) near the red wall (columns 8-10) over the
    // same near the green wall (columns 20-22). Direct light alone gives the light's own
    // colour on both sides: a ratio of 1.
    auto red_over_green = [](const Image& im, int x0) {
        return mean(im, x0, 8, x0 + 3, 12, 0) / mean(im, x0, 8, x0 + 3, 12, 1);
    };
    auto sides = [&](const Image& im) { return red_over_green(im, 8) / red_over_green(im, 20); };
    EXPECT_NEAR(sides(whitted.color), 1.0, 0.02);
    EXPECT_GT(sides(path.color), 1.2);
}

}  // namespace
}  // namespace svetlo
