// The rasterizer's shadow techniques (render.shadows): each against the exact shadow of a
// sphere on a floor, and against the raytraced technique (shadow rays through the same
// triangles) where no closed form is at hand; their filters, their known cases (an omni
// light's six faces, the camera inside a shadow volume, open occluders, two lights), the
// same image on any thread count, and bad settings.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "contract_camera.h"
#include "svetlo/core/error.h"
#include "svetlo/core/rng.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/geometry/triangle_list.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/raster/shadow_techniques.h"
#include "svetlo/scene/scene_loader.h"
#include "test_scenes.h"

namespace svetlo {
namespace {

using json = nlohmann::json;
using test_scenes::floor_quad;

constexpr int kSize = 128;
const char* const kTechniques[] = {"raytraced", "map", "volume", "planar"};

RenderResult render(const json& j, int threads = 2, std::vector<std::string> debug = {}) {
    Scene scene = scene_from_json(j, "test.json");
    RenderOptions options;
    options.threads = threads;
    options.aovs = {"visibility", "depth"};
    options.debug_aovs = std::move(debug);
    return RasterRenderer().render(scene, options);
}

/// The visibility AOV of scene j with shadows ray-traced: the truth inside the rasterizer.
Image raytraced_visibility(json j) {
    j["render"]["shadows"] = "raytraced";
    return render(j).aovs.at("visibility");
}

/// A unit sphere's shadow on a floor, seen from above at an angle.
json sphere_on_floor(const json& light, const char* shadows) {
    return {{"camera", {{"position", {0, 5, 6}}, {"look_at", {0, 0, 0}}, {"fov", 45}}},
            {"film", {{"width", kSize}, {"height", kSize}}},
            {"render", {{"engine", "raster"}, {"shadows", shadows}, {"tessellation", 128}}},
            {"materials", {{"m", {{"type", "lambert"}, {"albedo", 0.8}}}}},
            {"lights", {light}},
            {"objects",
             {{{"type", "sphere"}, {"center", {0, 1.2, 0}}, {"radius", 0.8}, {"material", "m"}},
              floor_quad(5.0f, "m")}}};
}

const json kPoint = {{"type", "point"}, {"position", {1, 4, 0.5}}, {"intensity", 30}};
const json kSpot = {{"type", "spot"},  {"position", {1, 4, 0.5}}, {"direction", {-1, -4, -0.5}},
                    {"intensity", 30}, {"inner_angle", 30},       {"outer_angle", 40}};
const json kDirectional = {
    {"type", "directional"}, {"direction", {-0.4, -1, -0.2}}, {"irradiance", 2}};

/// The exact shadow on the floor at pixel (i, j): 1 shadowed, 0 lit, -1 near the edge (the
/// segment toward the light passes within `margin` of the sphere's surface) or not on the
/// visible floor.
int exact_shadow(const Camera& camera, const json& light, int i, int jj, float margin) {
    Ray ray = contract_camera_ray(camera, kSize, kSize, (static_cast<float>(i) + 0.5f) / kSize,
                                  (static_cast<float>(jj) + 0.5f) / kSize);
    if (!(ray.d.y < 0.0f)) return -1;
    vec3 x = ray.o + ray.d * (-ray.o.y / ray.d.y);
    if (std::abs(x.x) > 5.0f || std::abs(x.z) > 5.0f) return -1;
    const vec3 c(0.0f, 1.2f, 0.0f);
    const float r = 0.8f;
    // Hidden behind the sphere (or near its outline): not a floor pixel.
    const float along = glm::dot(c - ray.o, ray.d);
    if (glm::length(ray.o + along * ray.d - c) < r + margin) return -1;
    // Distance from the sphere's centre to the ray (or segment) from x toward the light.
    vec3 to_light;
    float reach = kInfinity;
    if (light["type"] == "directional") {
        to_light = -glm::normalize(
            vec3(light["direction"][0], light["direction"][1], light["direction"][2]));
    } else {
        vec3 p(light["position"][0], light["position"][1], light["position"][2]);
        reach = glm::length(p - x);
        to_light = (p - x) / reach;
    }
    float t = std::clamp(glm::dot(c - x, to_light), 0.0f, reach);
    float d = glm::length(x + t * to_light - c);
    if (std::abs(d - r) < margin) return -1;
    return d < r ? 1 : 0;
}

struct ShadowCase {
    const char* technique;
    const char* light;
};

class SphereShadow : public ::testing::TestWithParam<ShadowCase> {};

TEST_P(SphereShadow, MatchesTheExactShadowAwayFromItsEdge) {
    const ShadowCase c = GetParam();
    const json& light = std::string(c.light) == "point"  ? kPoint
                        : std::string(c.light) == "spot" ? kSpot
                                                         : kDirectional;
    const json j = sphere_on_floor(light, c.technique);
    RenderResult r = render(j);
    const Image& v = r.aovs.at("visibility");
    const Camera camera = scene_from_json(j, "test.json").camera;
    int both = 0, either = 0, lit = 0, acne = 0;
    for (int jj = 0; jj < kSize; ++jj) {
        for (int i = 0; i < kSize; ++i) {
            int exact = exact_shadow(camera, light, i, jj, 0.05f);
            if (exact < 0) continue;
            bool shadowed = v.at(i, jj).r < 0.5f;
            both += exact == 1 && shadowed;
            either += exact == 1 || shadowed;
            if (exact == 0) {
                ++lit;
                acne += v.at(i, jj).r < 1.0f;  // any darkening of a lit floor is acne
            }
        }
    }
    ASSERT_GT(either, 200) << "the shadow is in view";
    ASSERT_GT(lit, 5000);
    EXPECT_GE(static_cast<double>(both) / either, 0.995) << c.technique << " " << c.light;
    EXPECT_EQ(acne, 0) << c.technique << " " << c.light;
}

INSTANTIATE_TEST_SUITE_P(
    EveryTechniqueAndLight, SphereShadow,
    ::testing::Values(ShadowCase{"raytraced", "point"}, ShadowCase{"map", "point"},
                      ShadowCase{"volume", "point"}, ShadowCase{"planar", "point"},
                      ShadowCase{"raytraced", "spot"}, ShadowCase{"map", "spot"},
                      ShadowCase{"volume", "spot"}, ShadowCase{"planar", "spot"},
                      ShadowCase{"raytraced", "directional"}, ShadowCase{"map", "directional"},
                      ShadowCase{"volume", "directional"}, ShadowCase{"planar", "directional"}),
    [](const auto& test) {
        return std::string(test.param.technique) + "_" + std::string(test.param.light);
    });

/// Pixels whose visibility lies strictly between 0 and 1.
int partial_pixels(const Image& v) {
    int n = 0;
    for (const Color& c : v.pixels) n += c.r > 0.02f && c.r < 0.98f;
    return n;
}

/// Mean |a - b| over the pixels.
double mean_difference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (size_t k = 0; k < a.pixels.size(); ++k) sum += std::abs(a.pixels[k].r - b.pixels[k].r);
    return sum / static_cast<double>(a.pixels.size());
}

TEST(ShadowMap, PcfGivesIntermediateValuesAlongTheEdgeAndNoneGivesNone) {
    json j = sphere_on_floor(kPoint, "map");
    j["render"]["shadow_map"] = {{"filter", "none"}, {"resolution", 512}};
    const int hard = partial_pixels(render(j).aovs.at("visibility"));
    j["render"]["shadow_map"] = {{"filter", "pcf"}, {"kernel", 7}, {"resolution", 512}};
    const int soft = partial_pixels(render(j).aovs.at("visibility"));
    EXPECT_EQ(hard, 0);
    EXPECT_GT(soft, 100);
}

/// The floor of floor_quad(half) as an inline mesh of n x n cells (2 n^2 triangles, facing +y).
json grid_floor(float half, int n, const char* material) {
    json positions = json::array(), indices = json::array();
    for (int k = 0; k <= n; ++k) {
        for (int i = 0; i <= n; ++i) {
            positions.push_back(
                {-half + 2.0f * half * static_cast<float>(i) / static_cast<float>(n), 0.0f,
                 -half + 2.0f * half * static_cast<float>(k) / static_cast<float>(n)});
        }
    }
    for (int k = 0; k < n; ++k) {
        for (int i = 0; i < n; ++i) {
            const int a = k * (n + 1) + i, b = a + n + 1, c = b + 1, d = a + 1;
            for (int v : {a, b, c, a, c, d}) indices.push_back(v);
        }
    }
    return {
        {"type", "mesh"}, {"positions", positions}, {"indices", indices}, {"material", material}};
}

TEST(ShadowMap, SmallTrianglesLookUpTheSamePointsAsLargeOnes) {
    // With one sample per pixel the masks take a small triangle's screen barycentrics from the
    // rasterizer, and a large one's from its edge functions. The same floor as one quad (two
    // large triangles) and as 2,048 small ones must be shadowed alike, but for rounding at the
    // shadow's edge; a sample looked up at another point of its small triangle moves the edge.
    json quad = sphere_on_floor(kSpot, "map");
    quad["render"]["spp"] = 1;
    quad["render"]["shadow_map"] = {{"filter", "none"}};
    json fine = quad;
    fine["objects"][1] = grid_floor(5.0f, 32, "m");
    const Image a = render(quad).aovs.at("visibility"), b = render(fine).aovs.at("visibility");
    int shadowed = 0, differ = 0;
    for (size_t k = 0; k < a.pixels.size(); ++k) {
        shadowed += a.pixels[k].r < 0.5f;
        differ += std::abs(a.pixels[k].r - b.pixels[k].r) > 0.5f;
    }
    EXPECT_GT(shadowed, 300);
    EXPECT_LE(differ, 4);
}

json area_light_scene(const char* shadows) {
    json j = sphere_on_floor(json::object(), shadows);
    j["lights"] = {{{"type", "area"},
                    {"corner", {0.5, 4, 0}},
                    {"edge_u", {1, 0, 0}},
                    {"edge_v", {0, 0, 1}},
                    {"radiance", 20}}};
    return j;
}

TEST(ShadowMap, PcssUnderAnAreaLightFollowsTheUnoccludedFraction) {
    json j = area_light_scene("map");
    j["render"]["shadow_map"] = {{"filter", "pcss"}, {"kernel", 7}};
    const Image pcss = render(j).aovs.at("visibility");
    const Image truth = render(area_light_scene("raytraced")).aovs.at("visibility");
    EXPECT_GT(partial_pixels(truth), 300) << "a penumbra to follow";
    EXPECT_GT(partial_pixels(pcss), partial_pixels(truth) / 2);
    EXPECT_LT(mean_difference(pcss, truth), 0.01);
    // A hard map (one caster at the light's centre would give no penumbra at all).
    j["render"]["shadow_map"] = {{"filter", "none"}};
    j["render"]["area_shadow_points"] = 1;
    const Image hard = render(j).aovs.at("visibility");
    EXPECT_GT(mean_difference(hard, truth), mean_difference(pcss, truth));
}

TEST(ShadowTechniques, AnAreaLightAsPointLightsFollowsTheUnoccludedFraction) {
    const Image truth = render(area_light_scene("raytraced")).aovs.at("visibility");
    for (const char* technique : {"map", "volume", "planar"}) {
        const Image v = render(area_light_scene(technique)).aovs.at("visibility");
        EXPECT_GT(partial_pixels(v), 300) << technique;
        EXPECT_LT(mean_difference(v, truth), 0.01) << technique;
    }
}

/// A point light in the middle of a closed room, with a small cube beyond it on every side,
/// seen from two opposite corners (together they see all six walls).
json omni_room(const char* shadows, int corner) {
    json objects = json::array();
    objects.push_back(
        {{"type", "box"}, {"min", {-3, -3, -3}}, {"max", {3, 3, 3}}, {"material", "m"}});
    for (int axis = 0; axis < 3; ++axis) {
        for (int sign : {-1, 1}) {
            json lo = {-0.3, -0.3, -0.3}, hi = {0.3, 0.3, 0.3};
            lo[axis] = sign * 1.2 - 0.3;
            hi[axis] = sign * 1.2 + 0.3;
            objects.push_back({{"type", "box"}, {"min", lo}, {"max", hi}, {"material", "m"}});
        }
    }
    float s = corner == 0 ? 2.7f : -2.7f;
    return {{"camera", {{"position", {s, s, s}}, {"look_at", {0, 0, 0}}, {"fov", 100}}},
            {"film", {{"width", kSize}, {"height", kSize}}},
            {"render", {{"engine", "raster"}, {"shadows", shadows}}},
            {"materials", {{"m", {{"type", "lambert"}, {"albedo", 0.8}}}}},
            {"lights", {{{"type", "point"}, {"position", {0.05, 0.1, 0.15}}, {"intensity", 30}}}},
            {"objects", objects}};
}

/// Intersection over union of the shadowed (< 0.5) pixels of two visibility images.
double shadow_iou(const Image& a, const Image& b, int* shadowed = nullptr) {
    int both = 0, either = 0;
    for (size_t k = 0; k < a.pixels.size(); ++k) {
        bool sa = a.pixels[k].r < 0.5f, sb = b.pixels[k].r < 0.5f;
        both += sa && sb;
        either += sa || sb;
    }
    if (shadowed) *shadowed = either;
    return either == 0 ? 1.0 : static_cast<double>(both) / either;
}

/// The scene's visibility AOV against the raytraced technique's on the same triangles: their
/// intersection over union, and how many pixels either shadows.
struct ShadowMatch {
    double iou = 0.0;
    int shadowed = 0;
};
ShadowMatch match_raytraced(const json& j) {
    ShadowMatch m;
    m.iou = shadow_iou(render(j).aovs.at("visibility"), raytraced_visibility(j), &m.shadowed);
    return m;
}

TEST(ShadowTechniques, AnOmniLightCastsOnEverySide) {
    for (const char* technique : {"map", "volume"}) {
        for (int corner : {0, 1}) {
            const Image truth = render(omni_room("raytraced", corner)).aovs.at("visibility");
            const Image v = render(omni_room(technique, corner)).aovs.at("visibility");
            int shadowed = 0;
            EXPECT_GT(shadow_iou(v, truth, &shadowed), 0.97) << technique << " corner " << corner;
            EXPECT_GT(shadowed, 700) << "three walls' shadows in view";
        }
    }
}

TEST(ShadowTechniques, AnEmptyRoomLitFromInsideHasNoShadowInItsCorners) {
    // Concave edges: a rasterized point near one is interpolated, and may lie a rounding
    // error behind the other wall (the raytraced technique shadowed 96 such pixels).
    for (const char* technique : kTechniques) {
        json j = omni_room(technique, 0);
        j["objects"] = {j["objects"][0]};
        j["camera"] = {{"position", {0, 0, -2}}, {"look_at", {0, 0, 0}}, {"fov", 100}};
        const Image v = render(j).aovs.at("visibility");
        int shadowed = 0;
        for (const Color& c : v.pixels) shadowed += c.r < 1.0f;
        EXPECT_EQ(shadowed, 0) << technique;
    }
}

TEST(ShadowVolumes, TheCameraInsideAShadowVolumeSeesTheSameShadows) {
    // The camera under the sphere, in its shadow, looking across the floor: z-pass would
    // count wrong here.
    json j = sphere_on_floor(kPoint, "volume");
    j["camera"] = {{"position", {-0.3, 0.3, -0.2}}, {"look_at", {-2, 0, -3}}, {"fov", 60}};
    const ShadowMatch m = match_raytraced(j);
    EXPECT_GT(m.iou, 0.99);
    EXPECT_GT(m.shadowed, 500);
}

TEST(ShadowVolumes, ZPassCountsWrongWithTheCameraInsideAndZFailRight) {
    // The teaching switch render.shadow_volume.count: z-pass is what the docs show failing.
    json j = sphere_on_floor(kPoint, "raytraced");
    j["camera"] = {{"position", {-0.3, 0.3, -0.2}}, {"look_at", {-2, 0, -3}}, {"fov", 60}};
    const Image truth = render(j).aovs.at("visibility");
    j["render"]["shadows"] = "volume";
    j["render"]["shadow_volume"] = {{"count", "zpass"}};
    EXPECT_LT(shadow_iou(render(j).aovs.at("visibility"), truth), 0.5);
    // From outside every volume both counts agree.
    j["camera"] = sphere_on_floor(kPoint, "volume")["camera"];
    const Image outside = render(j).aovs.at("visibility");
    EXPECT_GT(shadow_iou(outside, raytraced_visibility(j)), 0.99);
}

TEST(ShadowVolumes, ZPassWhereTheNearPlaneIsOutsideEveryVolumeCountsAsZFail) {
    // `auto` (the default) counts each light's volumes z-pass unless they may reach the near
    // plane: from outside, the same masks as z-fail, for every light type.
    for (const json& light : {kPoint, kSpot, kDirectional}) {
        json j = sphere_on_floor(light, "volume");
        const Image automatic = render(j).aovs.at("visibility");
        j["render"]["shadow_volume"] = {{"count", "zfail"}};
        const Image zfail = render(j).aovs.at("visibility");
        EXPECT_EQ(automatic.pixels, zfail.pixels) << light.dump();
    }
}

TEST(ShadowVolumes, AQuadCulledFromTheCameraStillCastsItsShadow) {
    // With back faces culled, a quad the camera sees from behind is not in the depth buffer:
    // z-pass must then count its near cap (without culling it draws the sides alone).
    for (const char* cull : {"none", "back"}) {
        json j = sphere_on_floor(kPoint, "volume");
        j["render"]["cull"] = cull;
        // Its front (edge_u x edge_v) faces down and away from the camera, toward the floor.
        j["objects"] = {{{"type", "quad"},
                         {"corner", {-0.5, 1.5, 0.5}},
                         {"edge_u", {0, 0, -1}},
                         {"edge_v", {1, 0, 0}},
                         {"material", "m"}},
                        floor_quad(5.0f, "m")};
        const ShadowMatch m = match_raytraced(j);
        EXPECT_GT(m.iou, 0.98) << cull;
        EXPECT_GT(m.shadowed, 200) << cull;
    }
}

TEST(ShadowVolumes, ObjectsSharingAnEdgeCloseTheirVolumesWithTheCameraInside) {
    // A wall standing on the floor's back edge (the adjacency joins them across objects, so
    // their sides there cancel), under an area light whose own quad's volume holds the camera
    // (z-fail): each object's far caps at infinity must still close on that edge. They did
    // not, and a quarter of the floor went dark.
    json j = area_light_scene("volume");
    j["objects"].push_back({{"type", "quad"},
                            {"corner", {-5, 0, -5}},
                            {"edge_u", {10, 0, 0}},
                            {"edge_v", {0, 4, 0}},
                            {"material", "m"}});
    const Image v = render(j).aovs.at("visibility");
    const Image truth = raytraced_visibility(j);
    EXPECT_LT(mean_difference(v, truth), 0.01);
}

TEST(PlanarShadows, WithoutTheSlabAnOccluderAboveTheLightCastsAFalseShadow) {
    // A quad 2 m above the point light: clipped away it casts nothing; projected whole
    // through the light it lands, mirrored, on the floor (render.planar_shadows.clip false,
    // the docs' picture).
    json j = sphere_on_floor(kPoint, "planar");
    j["objects"] = {{{"type", "quad"},
                     {"corner", {0.5, 6, 0}},
                     {"edge_u", {1, 0, 0}},
                     {"edge_v", {0, 0, 1}},
                     {"material", "m"}},
                    floor_quad(5.0f, "m")};
    auto shadowed = [&] {
        const RenderResult r = render(j);
        int n = 0;
        for (const Color& c : r.aovs.at("visibility").pixels) n += c.r < 0.5f;
        return n;
    };
    EXPECT_EQ(shadowed(), 0);
    j["render"]["planar_shadows"] = {{"clip", false}};
    EXPECT_GT(shadowed(), 100);
}

TEST(ShadowTechniques, OpenOccludersCastTheirShadows) {
    // A quad, a box without its top (an open mesh), and a box with a hole in its bottom.
    json open_box = {{"type", "mesh"},
                     {"positions", {-0.5, 1, -0.5, 0.5, 1, -0.5, 0.5, 1, 0.5, -0.5, 1, 0.5,
                                    -0.5, 2, -0.5, 0.5, 2, -0.5, 0.5, 2, 0.5, -0.5, 2, 0.5}},
                     // bottom and four sides, no top
                     {"indices", {0, 1, 2, 0, 2, 3, 0, 4, 5, 0, 5, 1, 1, 5, 6,
                                  1, 6, 2, 2, 6, 7, 2, 7, 3, 3, 7, 4, 3, 4, 0}},
                     {"material", "m"},
                     {"transform", {{"translate", {-1.5, 0, 0}}}}};
    json quad = {{"type", "quad"},
                 {"corner", {0.8, 1.5, -0.5}},
                 {"edge_u", {1, 0, 0}},
                 {"edge_v", {0, 0.2, 1}},
                 {"material", "m"}};
    for (const char* technique : {"map", "volume", "planar"}) {
        json j = sphere_on_floor(kPoint, technique);
        j["lights"] = {{{"type", "point"}, {"position", {0, 5, 0}}, {"intensity", 40}}};
        j["objects"] = {open_box, quad, floor_quad(5.0f, "m")};
        const ShadowMatch m = match_raytraced(j);
        EXPECT_GT(m.iou, 0.98) << technique;
        EXPECT_GT(m.shadowed, 400) << technique;
    }
}

TEST(ShadowTechniques, TwoLightsEachHaveTheirOwnMask) {
    // Where only one light is blocked the other still lights: the image is the ray-traced
    // one, which darkening the finished image could not give.
    for (const char* technique : {"map", "volume", "planar"}) {
        json j = sphere_on_floor(kPoint, technique);
        j["lights"] = {kPoint, {{"type", "point"}, {"position", {-2, 3, 1}}, {"intensity", 20}}};
        const RenderResult r = render(j);
        j["render"]["shadows"] = "raytraced";
        const RenderResult truth = render(j);
        j["render"]["shadows"] = "none";
        const RenderResult unshadowed = render(j);
        double error = 0.0, shadow = 0.0;
        for (size_t k = 0; k < r.color.pixels.size(); ++k) {
            error += std::abs(luminance(r.color.pixels[k]) - luminance(truth.color.pixels[k]));
            shadow +=
                std::abs(luminance(unshadowed.color.pixels[k]) - luminance(truth.color.pixels[k]));
        }
        EXPECT_GT(shadow, 50.0) << "the shadows matter";
        EXPECT_LT(error, 0.03 * shadow) << technique;
    }
}

TEST(ShadowTechniques, FlatAndGouraudShadingMultiplyEachLightByItsMask) {
    // One light, no ambient: a floor vertex or face in the full shadow gets no light at all.
    for (const char* shading : {"flat", "gouraud"}) {
        json j = sphere_on_floor(kPoint, "volume");
        j["render"]["shading"] = shading;
        const RenderResult r = render(j);
        const Image& v = r.aovs.at("visibility");
        const json unshadowed_scene = [&] {
            json u = j;
            u["render"]["shadows"] = "none";
            return u;
        }();
        const RenderResult u = render(unshadowed_scene);
        int dark = 0, in_shadow = 0;
        for (size_t k = 0; k < v.pixels.size(); ++k) {
            if (v.pixels[k].r != 0.0f) continue;
            ++in_shadow;
            // Gouraud interpolates each light's vertex terms, then masks: 0 in full shadow.
            dark += luminance(r.color.pixels[k]) == 0.0f && luminance(u.color.pixels[k]) > 0.0f;
        }
        EXPECT_GT(in_shadow, 200) << shading;
        EXPECT_EQ(dark, in_shadow) << shading;
    }
}

// The raytraced technique answers many samples at once (lit_many: the rays made 64 at a time
// lane by lane and traced as packets toward each caster) as it answers one (lit(): one ray,
// one traversal), for every kind of caster: point, spot, directional and an area light's
// VPLs; for samples on the floor and the sphere, on both sides, at their triangles' vertices
// and edges and inside, in rows as a tile gives them. lit_many's rays leave the convex object
// they start on (the sphere seen from outside, the floor) untested, lit()'s test it.
TEST(RaytracedShadows, ManySamplesAtOnceAnswerAsOneByOne) {
    json j = sphere_on_floor(kPoint, "raytraced");
    j["lights"] = {kPoint,
                   kSpot,
                   kDirectional,
                   {{"type", "area"},
                    {"corner", {0.5, 4, 0}},
                    {"edge_u", {1, 0, 0}},
                    {"edge_v", {0, 0, 1}},
                    {"radiance", 20}}};
    j["render"]["area_light_points"] = 4;
    j["render"]["tessellation"] = 32;
    const Scene scene = scene_from_json(j, "test.json");
    raster::FrameShading f;
    f.scene = &scene;
    f.lights.emplace(scene);
    std::vector<const Object*> objects;
    for (const Object& o : scene.objects) objects.push_back(&o);
    const TriangleList list = build_triangle_list(objects, tessellation_options(scene.render), 1);
    // Kept cubes, as svetlo serve keeps them: each point caster's rays culled by its cube.
    OccluderCubeCache cubes;
    raster::FrameCaches caches;
    caches.occluder_cubes = &cubes;
    caches.list_key = "the test's list";
    const auto technique = raster::make_raytraced_shadows(scene, list, f, caches, 2, nullptr);
    ASSERT_EQ(technique->casters().size(), 3u + 4u);
    // One for the point and the spot (their rays end at one point), one a point of the area.
    EXPECT_EQ(cubes.builds(), 1 + 4);

    std::vector<raster::ShadowSample> samples;
    Rng rng(7, 1);
    for (size_t t = 0; t < list.triangle_count(); ++t) {
        const vec3 a = list.positions[list.indices[3 * t]],
                   b = list.positions[list.indices[3 * t + 1]],
                   c = list.positions[list.indices[3 * t + 2]];
        const vec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (!std::isfinite(n.x)) continue;  // a pole's sliver
        // A vertex, an edge's middle, and a point inside; the side of the normal at random.
        const float u = rng.next_float(), v = rng.next_float() * (1.0f - u);
        for (vec3 p : {a, 0.5f * (a + b), a + u * (b - a) + v * (c - a)}) {
            raster::ShadowSample s;
            s.p = p;
            s.n = rng.next_float() < 0.8f ? n : -n;
            s.triangle = static_cast<uint32_t>(t);  // lit_many's rays skip a convex object's
            const int index = static_cast<int>(samples.size());
            s.i = index % 256;  // rows of 256 "pixels", in order
            s.j = index / 256;
            samples.push_back(s);
        }
    }
    int shadowed = 0, lit = 0, clear = 0;
    for (size_t k = 0; k < technique->casters().size(); ++k) {
        const ShadowCaster& caster = technique->casters()[k];
        // As fill_masks asks: a sample the caster's occluder cube calls clear is lit, the
        // others go to lit_many.
        const OccluderCube* cube = technique->occluders(k);
        EXPECT_EQ(cube == nullptr, caster.kind == ShadowCaster::Kind::Directional) << k;
        std::vector<uint32_t> facing;
        for (size_t m = 0; m < samples.size(); ++m) {
            if (!caster.faces(samples[m].p, samples[m].n)) continue;
            if (cube && cube->clear(samples[m].p, samples[m].n, samples[m].triangle)) {
                ASSERT_EQ(technique->lit(k, samples[m]), 1.0f)
                    << "caster " << k << ", sample " << m << " called clear";
                ++clear;
                continue;
            }
            facing.push_back(static_cast<uint32_t>(m));
        }
        std::vector<float> many(facing.size(), -1.0f);
        technique->lit_many(k, samples.data(), facing.data(), facing.size(), many.data());
        for (size_t m = 0; m < facing.size(); ++m) {
            const float one = technique->lit(k, samples[facing[m]]);
            ASSERT_EQ(many[m], one) << "caster " << k << ", sample " << facing[m];
            (one == 0.0f ? shadowed : lit) += 1;
        }
    }
    // Both answers occur, many times, and the cubes answer for many.
    EXPECT_GT(shadowed, 1000);
    EXPECT_GT(lit, 1000);
    EXPECT_GT(clear, 1000);
}

TEST(ShadowTechniques, EveryTechniqueGivesTheSameImageOnOneAndTwoThreads) {
    for (const char* technique : kTechniques) {
        json j = area_light_scene(technique);
        j["render"]["spp"] = 4;
        const RenderResult one = render(j, 1), two = render(j, 2);
        EXPECT_EQ(one.color.pixels, two.color.pixels) << technique;
        EXPECT_EQ(one.aovs.at("visibility").pixels, two.aovs.at("visibility").pixels) << technique;
    }
}

TEST(ShadowTechniques, ManySamplePassesKeepTheirMasks) {
    // More than 16 samples per pixel take several passes, each with its own masks.
    for (const char* technique : {"volume", "planar"}) {
        json j = sphere_on_floor(kPoint, technique);
        j["render"]["spp"] = 20;
        const Image v = render(j).aovs.at("visibility");
        const Image truth = raytraced_visibility(j);
        EXPECT_LT(mean_difference(v, truth), 0.005) << technique;
    }
}

TEST(ShadowTechniques, TheDebugBuffersShowTheMapAndTheCount) {
    RenderResult map = render(sphere_on_floor(kPoint, "map"), 2, {"shadow_map"});
    const Image& m = map.aovs.at("shadow_map");
    EXPECT_EQ(m.width, 4 * 2048);  // a cube map unfolded: four faces across, three down
    EXPECT_EQ(m.height, 3 * 2048);
    RenderResult volume = render(sphere_on_floor(kPoint, "volume"), 2, {"stencil"});
    const Image& s = volume.aovs.at("stencil");
    const Image& v = volume.aovs.at("visibility");
    int counted = 0;
    for (size_t k = 0; k < s.pixels.size(); ++k) {
        if (v.pixels[k].r == 0.0f) {
            EXPECT_NE(s.pixels[k].r, 0.0f);  // counted where shadowed
        }
        counted += s.pixels[k].r != 0.0f;
    }
    EXPECT_GT(counted, 300);
    EXPECT_THROW(render(sphere_on_floor(kPoint, "volume"), 2, {"shadow_map"}), Error);
}

TEST(ShadowSettings, BadValuesAreRefusedNamingTheKey) {
    const std::pair<const char*, json> bad[] = {
        {"resolution", 0}, {"bias", -0.1},  {"kernel", 0},         {"kernel", 65},
        {"filter", "box"}, {"cascades", 9}, {"normal_offset", -1}, {"slope_bias", -1}};
    for (const auto& [key, value] : bad) {
        json j = sphere_on_floor(kPoint, "map");
        j["render"]["shadow_map"] = {{key, value}};
        try {
            scene_from_json(j, "test.json");
            ADD_FAILURE() << key << " = " << value.dump() << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("render.shadow_map.") + key),
                      std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace svetlo
