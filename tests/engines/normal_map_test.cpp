// Normal maps (docs/real-scenes.md, "Normal maps") against the closed form in the engines that
// shade per point: a square of Lambert albedo 0.5 whose map holds one tilted normal, under a
// directional light of irradiance pi tilted 45 degrees from the square's normal, has radiance
// 0.5 cos(angle between the tilted normal and the light). Tilts along the tangent and the
// bitangent, toward the light and away from it; a quad (the ray tracers' analytic shape, its
// tangent from its edges) and a mesh (its tangents made as MikkTSpace makes them); both
// windings, so that the viewer sees the front and then the back.
#include <gtest/gtest.h>

#include <filesystem>

#include "image_means.h"
#include "render_json.h"
#include "svetlo/core/image_io.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"
#include "svetlo/shading/bsdf.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A 4 x 4 linear PFM whose every texel encodes the tangent-space normal n, (n + 1) / 2.
std::string write_normal_map(const std::string& name, vec3 n) {
    Image im(4, 4, 0.5f * (glm::normalize(n) + vec3(1.0f)));
    const fs::path path = fs::temp_directory_path() / ("svetlo_normal_" + name + ".pfm");
    write_image(path, im, PixelMeaning::Radiance, 1.0f, "test");
    return path.string();
}

struct Square {
    vec3 corner, edge_u, edge_v;
};

json square_object(const Square& s, bool as_mesh) {
    if (!as_mesh) {
        return {{"type", "quad"},
                {"corner", {s.corner.x, s.corner.y, s.corner.z}},
                {"edge_u", {s.edge_u.x, s.edge_u.y, s.edge_u.z}},
                {"edge_v", {s.edge_v.x, s.edge_v.y, s.edge_v.z}},
                {"material", "mapped"}};
    }
    json positions = json::array();
    for (vec3 p :
         {s.corner, s.corner + s.edge_u, s.corner + s.edge_u + s.edge_v, s.corner + s.edge_v})
        positions.push_back({p.x, p.y, p.z});
    return {{"type", "mesh"},
            {"positions", positions},
            {"uvs", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
            {"indices", {0, 1, 2, 0, 2, 3}},
            {"material", "mapped"}};
}

json scene_of(const Square& s, bool as_mesh, const std::string& map, vec3 light_travel,
              const char* engine) {
    return {
        {"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 20}}},
        {"film", {{"width", 16}, {"height", 16}}},
        {"render", {{"engine", engine}, {"spp", 4}, {"max_depth", 1}}},
        {"materials",
         {{"mapped", {{"type", "lambert"}, {"albedo", 0.5}, {"normal_map", {{"texture", map}}}}}}},
        {"lights",
         {{{"type", "directional"},
           {"direction", {light_travel.x, light_travel.y, light_travel.z}},
           {"irradiance", kPi}}}},
        {"objects", {square_object(s, as_mesh)}}};
}

template <class Engine>
void expect_mapped_radiance(const char* engine) {
    // The square faces the camera (+z) or, wound the other way, away from it.
    const Square front{vec3(-1, -1, 0), vec3(2, 0, 0), vec3(0, 2, 0)};
    const Square back{vec3(-1, 1, 0), vec3(2, 0, 0), vec3(0, -2, 0)};
    const float s = std::sqrt(0.5f), tilt = radians(30.0f);
    for (const Square& sq : {front, back}) {
        const vec3 n = glm::normalize(glm::cross(sq.edge_u, sq.edge_v));
        const vec3 t = glm::normalize(sq.edge_u), b = glm::cross(n, t);
        const float side = n.z > 0.0f ? 1.0f : -1.0f;  // the seen side's normal is side * n
        for (vec3 local :
             {vec3(std::sin(tilt), 0, std::cos(tilt)), vec3(-std::sin(tilt), 0, std::cos(tilt)),
              vec3(0, std::sin(tilt), std::cos(tilt)), vec3(0, -std::sin(tilt), std::cos(tilt))}) {
            const std::string map =
                write_normal_map(std::to_string(local.x > 0) + std::to_string(local.x < 0) +
                                     std::to_string(local.y > 0),
                                 local);
            const vec3 mapped = side * (local.x * t + local.y * b + local.z * n);
            for (vec3 to_light : {vec3(s, 0, s), vec3(0, s, s)}) {
                const float expected = 0.5f * std::max(0.0f, glm::dot(mapped, to_light));
                for (bool as_mesh : {false, true}) {
                    const RenderResult r =
                        render_json<Engine>(scene_of(sq, as_mesh, map, -to_light, engine));
                    EXPECT_NEAR(mean(r.color, 6, 6, 10, 10, 0), expected, 2e-3)
                        << engine << (side > 0 ? " front" : " back")
                        << (as_mesh ? " mesh" : " quad") << " tilt (" << local.x << ", " << local.y
                        << ") light (" << to_light.x << ", " << to_light.y << ")";
                }
            }
        }
    }
}

TEST(NormalMap, TiltsTheShadingNormalAlongTangentAndBitangentInEveryPointShadingEngine) {
    expect_mapped_radiance<RasterRenderer>("raster");
    expect_mapped_radiance<WhittedRenderer>("whitted");
    expect_mapped_radiance<PathRenderer>("path");
}

/// A clear-coated square facing the camera (+z; as a quad or a mesh), its base black and
/// rough, its coat of roughness 0.3 with a map of its own that tilts the coat's normal 20
/// degrees toward +x (no base map), lit by a directional light of irradiance pi from
/// to_light. Each engine's radiance at the middle 4 x 4 pixels against eval_bsdf there with
/// that coat normal: f (n, wo, wi) pi cos, wo toward each pixel's centre on the square.
template <class Engine>
void expect_coat_normal(const char* engine) {
    const float tilt = radians(20.0f);
    const vec3 local(std::sin(tilt), 0.0f, std::cos(tilt));
    const std::string map = write_normal_map("coat", local);
    CookTorranceMaterial m;
    m.base_color = ColorSource::constant(Color(0.0f));
    m.roughness = 1.0f;
    m.clearcoat = ColorSource::constant(Color(1.0f));
    m.clearcoat_roughness = ColorSource::constant(Color(0.3f));
    Bsdf b = make_bsdf(Material(m), vec2(0.5f), std::vector<TextureImage>{});
    b.coat_normal = local;  // the square's tangent is +x, its normal +z
    const float s = std::sqrt(0.5f);
    const Square sq{vec3(-1, -1, 0), vec3(2, 0, 0), vec3(0, 2, 0)};
    for (const vec3 to_light : {vec3(s, 0, s), vec3(-s, 0, s)}) {
        double expected = 0.0;  // the mean over the middle pixels' centres
        const float half = std::tan(radians(10.0f)) * 4.0f;  // the film's half side at z = 0
        for (int j = 6; j < 10; ++j)
            for (int i = 6; i < 10; ++i) {
                const vec3 p((i + 0.5f - 8.0f) / 8.0f * half, (8.0f - j - 0.5f) / 8.0f * half, 0);
                const vec3 wo = glm::normalize(vec3(0, 0, 4) - p);
                expected += eval_bsdf(b, vec3(0, 0, 1), wo, to_light).g * kPi * to_light.z / 16.0;
            }
        for (bool as_mesh : {false, true}) {
            json scene = scene_of(sq, as_mesh, map, -to_light, engine);
            scene["materials"]["mapped"] = {
                {"type", "cook_torrance"},    {"base_color", 0.0},
                {"roughness", 1.0},           {"clearcoat", 1.0},
                {"clearcoat_roughness", 0.3}, {"clearcoat_normal_map", {{"texture", map}}}};
            const RenderResult r = render_json<Engine>(scene);
            EXPECT_NEAR(mean(r.color, 6, 6, 10, 10, 1), expected, 0.03 * expected)
                << engine << (as_mesh ? " mesh" : " quad") << " light x " << to_light.x;
        }
    }
}

TEST(NormalMap, AClearCoatReflectsAboutItsOwnMappedNormalInEveryPointShadingEngine) {
    expect_coat_normal<RasterRenderer>("raster");
    expect_coat_normal<WhittedRenderer>("whitted");
    expect_coat_normal<PathRenderer>("path");
}

}  // namespace
}  // namespace svetlo
