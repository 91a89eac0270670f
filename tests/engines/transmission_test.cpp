// Transmission on cook_torrance (glTF's KHR_materials_transmission and _ior; docs/real-scenes.md,
// "Transmission") against closed forms: a clear sheet (base colour 1, metallic 0, smooth)
// seen head-on before a uniform background B passes (1 - F0) B by refraction, F0 =
// ((ior - 1) / (ior + 1))^2, in Whitted and the rasterizer (which add no reflection of a
// uniform background) and B in the path tracer (which adds the reflection, F0 B, as well);
// without transmission the path tracer sees F0 B. Both windings. An absorbing inside
// (KHR_materials_volume) keeps Beer-Lambert's share along the path through it.
#include <gtest/gtest.h>

#include "image_means.h"
#include "render_json.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"
#include "svetlo/shading/bsdf.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

constexpr double kB = 2.0;  // the background's radiance

json sheet(bool front, double transmission, double ior, const char* engine) {
    json corner = front ? json{-1, -1, 0} : json{-1, 1, 0};
    json edge_v = front ? json{0, 2, 0} : json{0, -2, 0};
    return {{"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 4}}},
            {"film", {{"width", 8}, {"height", 8}}},
            {"render", {{"engine", engine}, {"spp", 64}, {"max_depth", 4}, {"background", kB}}},
            {"materials",
             {{"clear",
               {{"type", "cook_torrance"},
                {"base_color", 1.0},
                {"metallic", 0.0},
                {"roughness", 0.0},
                {"ior", ior},
                {"transmission", transmission}}}}},
            {"lights", json::array()},
            {"objects",
             {{{"type", "quad"},
               {"corner", corner},
               {"edge_u", {2, 0, 0}},
               {"edge_v", edge_v},
               {"material", "clear"}}}}};
}

double f0(double ior) { return std::pow((ior - 1.0) / (ior + 1.0), 2.0); }

TEST(Transmission, TheIorSetsTheDielectricsF0) {
    CookTorranceMaterial m;
    m.base_color = ColorSource::constant(Color(1.0f));
    m.ior = 2.0f;
    EXPECT_NEAR(make_bsdf(Material(m), vec2(0.0f), {}).specular.g, 1.0f / 9.0f, 1e-6f);
    m.ior = 1.5f;
    EXPECT_NEAR(make_bsdf(Material(m), vec2(0.0f), {}).specular.g, 0.04f, 1e-6f);
    m.transmission = ColorSource::constant(Color(0.25f));
    const Bsdf b = make_bsdf(Material(m), vec2(0.0f), {});
    EXPECT_NEAR(b.diffuse.r, 0.75f, 1e-6f);  // the dielectric's diffuse part, less what passes
    EXPECT_NEAR(b.transmit.r, 0.25f, 1e-6f);
}

template <class Engine>
void expect_refracted(const char* engine, double expected_share) {
    for (bool front : {true, false}) {
        for (double ior : {1.5, 2.0}) {
            const RenderResult r = render_json<Engine>(sheet(front, 1.0, ior, engine));
            // At a field of 4 degrees, cos_o > 0.9994: Schlick's F within 1e-13 of F0.
            const double expected = kB * (expected_share < 0.0 ? 1.0 : 1.0 - f0(ior));
            EXPECT_NEAR(mean(r.color, 1), expected, 2e-3 * kB)
                << engine << (front ? " front" : " back") << ", ior " << ior;
        }
    }
}

TEST(Transmission, WhittedAndTheRasterizerPassWhatFresnelLeaves) {
    expect_refracted<WhittedRenderer>("whitted", 0.0);
    expect_refracted<RasterRenderer>("raster", 0.0);
}

TEST(Transmission, ThePathTracerPassesAndReflectsTheWholeBackground) {
    expect_refracted<PathRenderer>("path", -1.0);
    // Without transmission the sheet's black diffuse part reflects nothing: F0 B remains.
    json opaque = sheet(true, 0.0, 1.5, "path");
    opaque["materials"]["clear"]["base_color"] = 0.0;
    EXPECT_NEAR(mean(render_json<PathRenderer>(opaque).color, 1), f0(1.5) * kB, 2e-3 * kB);
}

/// The directional albedo of a BSDF seen along its normal, reflection and transmission (or,
/// `reflection` false, the transmitted part alone: what passes, and the share that microfacets
/// reflect totally above): the integral of (f + f_t) |cos| over the sphere by the midpoint rule
/// in theta (fine at the poles, where the transmitted lobe narrows), which needs no sampler.
/// Seen along the normal the integrand does not depend on phi.
double albedo_along_normal(const Bsdf& b, bool front, bool reflection = true) {
    constexpr int kTheta = 20000;
    const vec3 n(0.0f, 0.0f, 1.0f);
    double sum = 0.0;
    for (int i = 0; i < kTheta; ++i) {
        const double theta = kPi * (i + 0.5) / kTheta;
        const vec3 wi(static_cast<float>(std::sin(theta)), 0.0f,
                      static_cast<float>(std::cos(theta)));
        Color f = eval_transmitted(b, n, n, wi, front);
        if (reflection) f += eval_bsdf(b, n, n, wi);
        sum += f.g * std::abs(std::cos(theta)) * std::sin(theta) * (kPi / kTheta) * 2.0 * kPi;
    }
    return sum;
}

/// The clear sheet of ior 1.5 at `roughness`, `spp` samples a pixel.
json rough_sheet(bool front, double roughness, int spp, const char* engine) {
    json scene = sheet(front, 1.0, 1.5, engine);
    scene["materials"]["clear"]["roughness"] = roughness;
    scene["render"]["spp"] = spp;
    return scene;
}
/// The BSDF of that sheet.
Bsdf rough_sheet_bsdf(float roughness) {
    CookTorranceMaterial m;
    m.base_color = ColorSource::constant(Color(1.0f));
    m.roughness = roughness;
    m.ior = 1.5f;
    m.transmission = ColorSource::constant(Color(1.0f));
    return make_bsdf(Material(m), vec2(0.0f), {});
}

TEST(Transmission, ARoughSheetPassesAndReflectsItsAlbedoOfTheBackground) {
    // A rough clear sheet (roughness 0.5) before a uniform background B: what the path tracer
    // sees is B times the sheet's albedo (reflection, and transmission through microfacets),
    // which the quadrature of eval_bsdf and eval_transmitted gives; both sides (entering, and
    // leaving, where microfacets reflect totally). A smooth sheet's albedo is 1; the rough
    // one's is less by what masking takes.
    for (bool front : {true, false}) {
        const double albedo = albedo_along_normal(rough_sheet_bsdf(0.5f), front);
        EXPECT_LT(albedo, 0.998);
        EXPECT_GT(albedo, 0.85);
        EXPECT_NEAR(mean(render_json<PathRenderer>(rough_sheet(front, 0.5, 256, "path")).color, 1),
                    albedo * kB, 3e-3 * kB)
            << (front ? "front" : "back");
    }
}

TEST(Transmission, WhittedPassesARoughSheetsTransmittedAlbedoOfTheBackground) {
    // A sheet of roughness 1 in Whitted: the background is no light, so what Whitted sees is
    // what the transmitted lobe passes, B times its albedo (the quadrature of
    // eval_transmitted), drawn through the same microfacets as the path tracer's; the ideal
    // refraction it took before passed (1 - F0) B. Both sides.
    for (bool front : {true, false}) {
        const double albedo = albedo_along_normal(rough_sheet_bsdf(1.0f), front, false);
        // Less than the ideal refraction's 1 - F0 = 0.96: 0.89 entering, 0.42 leaving (where
        // most microfacets reflect totally).
        EXPECT_LT(albedo, 0.9);
        EXPECT_NEAR(
            mean(render_json<WhittedRenderer>(rough_sheet(front, 1.0, 1024, "whitted")).color, 1),
            albedo * kB, 3e-3 * kB)
            << (front ? "front" : "back");
    }
}

/// A box of side 1 along the view (z from -1 to 0), of ior 1 (no reflection, no bending),
/// fully transmitting, whose inside keeps `keep` over `distance`: the background behind it is
/// seen through 1 unit of it, keep^(1 / distance) of B. Seen from +z, then from -z.
json absorbing_box(double keep, double distance, bool from_front, const char* engine) {
    json scene = sheet(true, 1.0, 1.0, engine);
    scene["materials"]["clear"]["attenuation_color"] = {keep, 1.0, 1.0};
    scene["materials"]["clear"]["attenuation_distance"] = distance;
    scene["objects"] = {
        {{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {1, 1, 0}}, {"material", "clear"}}};
    if (!from_front) scene["camera"]["position"] = {0, 0, -5};
    return scene;
}

template <class Engine>
void expect_absorbed(const char* engine) {
    for (bool from_front : {true, false}) {
        for (double distance : {0.5, 2.0}) {
            const RenderResult r =
                render_json<Engine>(absorbing_box(0.25, distance, from_front, engine));
            EXPECT_NEAR(mean(r.color, 0), kB * std::pow(0.25, 1.0 / distance), 2e-3 * kB)
                << engine << (from_front ? " from +z" : " from -z") << ", distance " << distance;
            EXPECT_NEAR(mean(r.color, 1), kB, 2e-3 * kB) << engine << " green is not absorbed";
        }
    }
}

TEST(Transmission, AVolumeAbsorbsAlongThePathInsideIt) {
    expect_absorbed<PathRenderer>("path");
    expect_absorbed<WhittedRenderer>("whitted");
}

}  // namespace
}  // namespace svetlo
