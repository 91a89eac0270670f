// A glTF's second texture coordinate set, its vertex colours and its occlusion texture
// (docs/real-scenes.md, "What a point reads") in every engine: a quad whose base colour is
// COLOR_0 renders as the quad whose factor is that colour; a texture read at TEXCOORD_1 (or
// moved there by KHR_texture_transform's texCoord) as the same texel read at TEXCOORD_0; and
// the occlusion texture darkens the ambient term by 1 + strength (r - 1); an unlit material
// shows its base colour. Both windings.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

/// What the quad's vertices carry (empty: not in the file), in glTF's texture space (v down).
struct QuadAttributes {
    std::vector<vec2> uv0, uv1;
    std::vector<vec4> colors;
};

/// Writes NAME.gltf and NAME.bin into the test's folder: the square [-1, 1]^2 at z = 0, its
/// front toward +z (or, `front` false, wound toward -z), with `attributes` and one material.
fs::path write_quad(const std::string& name, const QuadAttributes& attributes, const json& material,
                    bool front) {
    const fs::path dir = fs::temp_directory_path() / "svetlo_varyings";
    fs::create_directories(dir);
    // A 2 x 1 texture: red on the left, blue on the right (codes 255 in sRGB: 1).
    Image im(2, 1);
    im.at(0, 0) = Color(1.0f, 0.0f, 0.0f);
    im.at(1, 0) = Color(0.0f, 0.0f, 1.0f);
    write_image(dir / "two.png", im, PixelMeaning::Data, 1.0f, "test");

    std::vector<float> data;
    json accessors = json::array(), views = json::array(), attrs = json::object();
    auto add = [&](const char* key, const float* values, size_t components, const char* type) {
        const size_t offset = data.size() * sizeof(float);
        data.insert(data.end(), values, values + 4 * components);
        views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", 16 * components}});
        json a = {{"bufferView", views.size() - 1},
                  {"componentType", 5126},
                  {"count", 4},
                  {"type", type}};
        if (std::string(key) == "POSITION") a["min"] = {-1, -1, 0}, a["max"] = {1, 1, 0};
        accessors.push_back(a);
        attrs[key] = accessors.size() - 1;
    };
    const float positions[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    add("POSITION", positions, 3, "VEC3");
    auto add_set = [&](const char* key, const std::vector<vec2>& uv) {
        if (uv.empty()) return;
        std::vector<float> v;
        for (vec2 x : uv) v.insert(v.end(), {x.x, x.y});
        add(key, v.data(), 2, "VEC2");
    };
    add_set("TEXCOORD_0", attributes.uv0);
    add_set("TEXCOORD_1", attributes.uv1);
    if (!attributes.colors.empty()) {
        std::vector<float> v;
        for (vec4 c : attributes.colors) v.insert(v.end(), {c.r, c.g, c.b, c.a});
        add("COLOR_0", v.data(), 4, "VEC4");
    }
    const std::vector<uint16_t> indices =
        front ? std::vector<uint16_t>{0, 1, 2, 0, 2, 3} : std::vector<uint16_t>{0, 2, 1, 0, 3, 2};
    const size_t index_offset = data.size() * sizeof(float);
    views.push_back({{"buffer", 0}, {"byteOffset", index_offset}, {"byteLength", 12}});
    accessors.push_back({{"bufferView", views.size() - 1},
                         {"componentType", 5123},
                         {"count", 6},
                         {"type", "SCALAR"}});
    std::ofstream bin(dir / (name + ".bin"), std::ios::binary);
    bin.write(reinterpret_cast<const char*>(data.data()),
              static_cast<std::streamsize>(index_offset));
    bin.write(reinterpret_cast<const char*>(indices.data()), 12);
    bin.close();
    const json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"KHR_texture_transform"}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"meshes",
         {{{"primitives",
            {{{"attributes", attrs}, {"indices", accessors.size() - 1}, {"material", 0}}}}}}},
        {"materials", {material}},
        {"textures", {{{"source", 0}, {"sampler", 0}}}},
        {"samplers", {{{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}}},
        {"images", {{{"uri", "two.png"}}}},
        {"accessors", accessors},
        {"bufferViews", views},
        {"buffers", {{{"uri", name + ".bin"}, {"byteLength", index_offset + 12}}}}};
    std::ofstream(dir / (name + ".gltf")) << gltf.dump();
    return dir / (name + ".gltf");
}

/// A dielectric glTF material (metallic 0) of base colour factor `base`, doubleSided.
json material_of(vec3 base, const json& extra = json::object()) {
    json m = {{"doubleSided", true},
              {"pbrMetallicRoughness",
               {{"baseColorFactor", {base.r, base.g, base.b, 1}},
                {"metallicFactor", 0},
                {"roughnessFactor", 0.6}}}};
    m.merge_patch(extra);
    return m;
}

/// The quad seen from +z, lit by a directional light from behind the camera and an ambient
/// term.
json scene_with(const fs::path& model, const char* engine) {
    return {
        {"camera", {{"position", {0, 0, 4}}, {"look_at", {0, 0, 0}}, {"fov", 20}}},
        {"film", {{"width", 16}, {"height", 16}}},
        {"render", {{"engine", engine}, {"spp", 4}, {"max_depth", 2}, {"ambient", 0.1}}},
        {"lights", {{{"type", "directional"}, {"direction", {0.3, -0.2, -1}}, {"irradiance", 2}}}},
        {"objects", {{{"type", "mesh"}, {"file", model.string()}}}}};
}

template <class Engine>
void expect_same_image(const fs::path& a, const fs::path& b, const char* engine,
                       const std::string& what) {
    const RenderResult ra = render_json<Engine>(scene_with(a, engine));
    const RenderResult rb = render_json<Engine>(scene_with(b, engine));
    ASSERT_GT(mean(rb.color, 0) + mean(rb.color, 2), 0.01) << engine << " " << what << " is black";
    for (int y = 0; y < ra.color.height; ++y)
        for (int x = 0; x < ra.color.width; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(ra.color.at(x, y)[c], rb.color.at(x, y)[c], 1e-5f)
                    << engine << " " << what << " at " << x << ", " << y;
}

template <class Engine>
void expect_vertex_colour_is_the_factor(const char* engine) {
    const vec4 c(1.0f, 0.5f, 0.25f, 1.0f);
    for (bool front : {true, false}) {
        const fs::path colored =
            write_quad("colored", {{}, {}, {c, c, c, c}}, material_of(vec3(1.0f)), front);
        const fs::path factor = write_quad("factor", {}, material_of(vec3(c)), front);
        expect_same_image<Engine>(colored, factor, engine,
                                  std::string("COLOR_0, ") + (front ? "front" : "back"));
    }
}

TEST(Varyings, AVertexColourMultipliesTheBaseColourInEveryEngine) {
    expect_vertex_colour_is_the_factor<RasterRenderer>("raster");
    expect_vertex_colour_is_the_factor<WhittedRenderer>("whitted");
    expect_vertex_colour_is_the_factor<PathRenderer>("path");
    expect_vertex_colour_is_the_factor<RadiosityRenderer>("radiosity");
}

TEST(Varyings, AVertexColourVariesOverTheTriangle) {
    // Red on the left corners, blue on the right: the left columns (x from -0.71 to -0.35,
    // (x + 1) / 2 of the way to blue) about three parts red to one blue, the right ones the
    // other way round.
    const vec4 red(1, 0, 0, 1), blue(0, 0, 1, 1);
    const fs::path quad =
        write_quad("ramp", {{}, {}, {red, blue, blue, red}}, material_of(vec3(1.0f)), true);
    const RenderResult r = render_json<RasterRenderer>(scene_with(quad, "raster"));
    EXPECT_GT(mean(r.color, 0, 4, 4, 12, 0), 2.0 * mean(r.color, 0, 4, 4, 12, 2));
    EXPECT_GT(mean(r.color, 12, 4, 16, 12, 2), 2.0 * mean(r.color, 12, 4, 16, 12, 0));
}

template <class Engine>
void expect_second_set(const char* engine) {
    // TEXCOORD_0 on the red texel, TEXCOORD_1 on the blue one.
    const std::vector<vec2> red(4, vec2(0.25f, 0.5f)), blue(4, vec2(0.75f, 0.5f));
    for (bool front : {true, false}) {
        const std::string side = front ? "front" : "back";
        const fs::path first = write_quad(
            "first", {blue, {}, {}},
            material_of(vec3(1.0f),
                        {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}),
            front);
        const fs::path second = write_quad(
            "second", {red, blue, {}},
            material_of(vec3(1.0f), {{"pbrMetallicRoughness",
                                      {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}}}}),
            front);
        expect_same_image<Engine>(second, first, engine, "TEXCOORD_1, " + side);
        const fs::path moved = write_quad(
            "moved", {red, blue, {}},
            material_of(vec3(1.0f),
                        {{"pbrMetallicRoughness",
                          {{"baseColorTexture",
                            {{"index", 0},
                             {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}}}}}),
            front);
        expect_same_image<Engine>(moved, first, engine,
                                  "KHR_texture_transform's texCoord, " + side);
    }
}

template <class Engine>
void expect_unlit_base_colour(const char* engine) {
    // The blue texel (0, 0, 1) times the factor (1, 1, 0.5) times COLOR_0 (1, 1, 0.5): the
    // front shows radiance 0.25 in blue whatever the lights and the ambient term (a black
    // surface that emits its base colour), the back nothing (emission leaves the front).
    const std::vector<vec2> blue(4, vec2(0.75f, 0.5f));
    const vec4 c(1.0f, 1.0f, 0.5f, 1.0f);
    for (bool front : {true, false}) {
        const fs::path quad = write_quad(
            "unlit", {blue, {}, {c, c, c, c}},
            {{"pbrMetallicRoughness",
              {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {1, 1, 0.5, 1}}}},
             {"extensions", {{"KHR_materials_unlit", json::object()}}}},
            front);
        const RenderResult r = render_json<Engine>(scene_with(quad, engine));
        const std::string what = std::string(engine) + (front ? ", front" : ", back");
        for (int y = 0; y < r.color.height; ++y) {
            for (int x = 0; x < r.color.width; ++x) {
                const Color p = r.color.at(x, y);
                ASSERT_NEAR(p.b, front ? 0.25f : 0.0f, 1e-5f) << what << " at " << x << ", " << y;
                ASSERT_NEAR(p.r, 0.0f, 1e-5f) << what << " at " << x << ", " << y;
                ASSERT_NEAR(p.g, 0.0f, 1e-5f) << what << " at " << x << ", " << y;
            }
        }
    }
}

TEST(Varyings, AnUnlitMaterialShowsItsBaseColourTimesTheVertexColourInEveryEngine) {
    expect_unlit_base_colour<RasterRenderer>("raster");
    expect_unlit_base_colour<WhittedRenderer>("whitted");
    expect_unlit_base_colour<PathRenderer>("path");
    expect_unlit_base_colour<RadiosityRenderer>("radiosity");
}

TEST(Varyings, ATextureReadsTheSetItNamesInEveryEngine) {
    expect_second_set<RasterRenderer>("raster");
    expect_second_set<WhittedRenderer>("whitted");
    expect_second_set<PathRenderer>("path");
    expect_second_set<RadiosityRenderer>("radiosity");
}

template <class Engine>
void expect_occluded_ambient(const char* engine) {
    // No light but the ambient term 0.1 on a base colour of 1: 0.1 where the occlusion
    // texture's red is 1 (its right texel is blue: r = 0, 1 + 0.5 (0 - 1) = 0.5).
    for (bool front : {true, false}) {
        const std::vector<vec2> ramp = {{0, 0.5f}, {1, 0.5f}, {1, 0.5f}, {0, 0.5f}};
        const fs::path quad = write_quad(
            "occluded", {std::vector<vec2>(4, vec2(0.5f)), ramp, {}},
            material_of(vec3(1.0f),
                        {{"occlusionTexture", {{"index", 0}, {"texCoord", 1}, {"strength", 0.5}}}}),
            front);
        json scene = scene_with(quad, engine);
        scene["lights"] = json::array();
        const RenderResult r = render_json<Engine>(scene);
        EXPECT_NEAR(mean(r.color, 0, 4, 6, 12, 0), 0.1, 1e-5) << engine << " " << front;
        EXPECT_NEAR(mean(r.color, 10, 4, 16, 12, 0), 0.05, 1e-5) << engine << " " << front;
    }
}

TEST(Varyings, OcclusionDarkensTheAmbientTermOfRasterAndWhitted) {
    expect_occluded_ambient<RasterRenderer>("raster");
    expect_occluded_ambient<WhittedRenderer>("whitted");
}

}  // namespace
}  // namespace svetlo
