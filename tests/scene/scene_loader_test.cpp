#include "svetlo/scene/scene_loader.h"

#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "svetlo/core/error.h"

namespace svetlo {
namespace {

using json = nlohmann::json;

json minimal() {
    return json::parse(R"({
      "camera": {"position": [0, 1, 5], "look_at": [0, 1, 0]},
      "materials": {"white": {"type": "lambert", "albedo": 0.8}},
      "lights": [{"type": "point", "position": [0, 4, 0], "intensity": [10, 10, 10]}],
      "objects": [{"type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "white"}]
    })");
}

/// The "WHERE: WHAT" of the error that loading `j` raises.
std::string error_of(const json& j) {
    try {
        scene_from_json(j, "s.json");
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "s.json");
        return e.where() + ": " + e.message();
    }
    return "no error";
}

TEST(SceneLoader, AlphaIsANumberOrACoverageTextureWithItsModeAndCutoff) {
    // A 2 x 1 RGBA PNG: alpha 0 on the left, 200 on the right.
    const std::filesystem::path png =
        std::filesystem::temp_directory_path() / "svetlo_alpha_rgba.png";
    const unsigned char texels[8] = {255, 0, 0, 0, 0, 0, 255, 200};
    ASSERT_NE(stbi_write_png(png.c_str(), 2, 1, 4, texels, 8), 0);
    json j = minimal();
    j["materials"]["leaf"] = {{"type", "lambert"}, {"alpha", {{"texture", png.string()}}}};
    j["materials"]["veil"] = {
        {"type", "lambert"}, {"alpha", 0.3}, {"alpha_mode", "blend"}, {"alpha_cutoff", 0.25}};
    const Scene s = scene_from_json(j, "s.json");
    const auto material = [&](const std::string& name) {
        for (size_t k = 0; k < s.material_names.size(); ++k)
            if (s.material_names[k] == name) return s.materials[k];
        ADD_FAILURE() << name;
        return Material{};
    };
    EXPECT_EQ(material("white").alpha.mode, AlphaMode::Opaque);
    const Alpha leaf = material("leaf").alpha;
    EXPECT_EQ(leaf.mode, AlphaMode::Mask);  // alpha given: a mask unless told
    EXPECT_EQ(leaf.cutoff, 0.5f);
    ASSERT_EQ(leaf.coverage.kind, ColorSource::Kind::Image);
    const TextureImage& t = s.textures[static_cast<size_t>(leaf.coverage.texture)];
    EXPECT_EQ(t.texel(0, 0), Color(0.0f));                 // the alpha channel, not red
    EXPECT_NEAR(t.texel(1, 0).g, 200.0f / 255.0f, 1e-6f);  // linear, in every channel
    const Alpha veil = material("veil").alpha;
    EXPECT_EQ(veil.mode, AlphaMode::Blend);
    EXPECT_EQ(veil.coverage.value, Color(0.3f));
    EXPECT_EQ(veil.cutoff, 0.25f);
    j["materials"]["veil"]["alpha"] = 1.5;
    EXPECT_NE(error_of(j).find("materials.veil.alpha"), std::string::npos) << error_of(j);
    j["materials"]["veil"]["alpha"] = 0.3;
    j["materials"]["veil"]["alpha_mode"] = "dither";
    EXPECT_NE(error_of(j).find("materials.veil.alpha_mode"), std::string::npos) << error_of(j);
    std::filesystem::remove(png);
}

TEST(SceneLoader, MinimalSceneHasTheContractDefaults) {
    Scene s = scene_from_json(minimal(), "s.json");
    EXPECT_EQ(s.film.width, 512);
    EXPECT_EQ(s.render.engine, "whitted");
    EXPECT_EQ(s.render.spp, 1);
    EXPECT_EQ(s.render.max_depth, 5);
    EXPECT_EQ(s.render.exposure, 1.0f);
    EXPECT_EQ(s.camera.fov_deg, 40.0f);
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_EQ(std::get<Sphere>(s.objects[0].shape).radius, 1.0f);
}

TEST(SceneLoader, ErrorsNameTheJsonPath) {
    json j = minimal();
    j["objects"][0]["radius"] = -1;
    EXPECT_EQ(error_of(j), "objects[0].radius: must be > 0 (is -1)");
    j = minimal();
    j["objects"][0]["radius"] = 0;
    EXPECT_EQ(error_of(j), "objects[0].radius: must be > 0 (is 0)");
    j = minimal();
    j["objects"][0]["radius"] = "big";
    EXPECT_EQ(error_of(j), "objects[0].radius: must be a number, not a string");
    j = minimal();
    j["objects"][0].erase("radius");
    EXPECT_EQ(error_of(j), "objects[0].radius: missing key");
    j = minimal();
    j["materials"]["white"]["albedo"] = {
        {"texture", "t.png"}, {"filter", "anisotropic"}, {"max_anisotropy", 0}};
    EXPECT_EQ(error_of(j), "materials.white.albedo.max_anisotropy: must be in [1, 64] (is 0)");
    j = minimal();
    j["materials"]["white"]["albedo"] = {{"texture", "t.png"}, {"wrap", {"mirror"}}};
    EXPECT_EQ(error_of(j),
              "materials.white.albedo.wrap: expected one wrap mode, or two: [along u, along v]");
    j = minimal();
    j["materials"]["white"]["albedo"] = {{"texture", "t.png"}, {"wrap", {"mirror", "spiral"}}};
    EXPECT_NE(error_of(j).find("materials.white.albedo.wrap[1]: unknown value 'spiral'"),
              std::string::npos);
    j = minimal();
    j["objects"][0]["material"] = "gold";
    EXPECT_EQ(error_of(j), "objects[0].material: unknown material 'gold'");
    j = minimal();
    j["objects"][0]["type"] = "teapot";
    EXPECT_NE(error_of(j).find("objects[0].type: unknown value 'teapot'"), std::string::npos);
    j = minimal();
    j["lights"][0]["type"] = "laser";
    EXPECT_NE(error_of(j).find("lights[0].type: unknown value 'laser'"), std::string::npos);
    j = minimal();
    j["materials"]["white"]["type"] = "velvet";
    EXPECT_NE(error_of(j).find("materials.white.type: unknown value 'velvet'"), std::string::npos);
    j = minimal();
    // The engine's name is an open set here; the job layer's registry says which exist
    // (tests/app/cli_test.sh).
    j["render"] = {{"engine", 3}};
    EXPECT_NE(error_of(j).find("render.engine: must be a string"), std::string::npos);
    j = minimal();
    j["objects"][0]["raduis"] = 1;
    EXPECT_NE(error_of(j).find("objects[0].raduis: unknown key"), std::string::npos);
    j = minimal();
    j["lights"][0]["intensity"] = {1, 2};
    EXPECT_NE(error_of(j).find("lights[0].intensity: must be a colour"), std::string::npos);
}

TEST(SceneLoader, DegenerateCameraAndImpossibleFilm) {
    json j = minimal();
    j["camera"]["look_at"] = {0, 1, 5};
    EXPECT_NE(error_of(j).find("camera.look_at: must differ from position"), std::string::npos);
    j = minimal();
    j["camera"]["up"] = {0, 0, -2};
    EXPECT_NE(error_of(j).find("up is parallel"), std::string::npos);
    j = minimal();
    j["film"] = {{"width", 60000}, {"height", 60000}};
    EXPECT_NE(error_of(j).find("film: film of 60000 x 60000 pixels is too large"),
              std::string::npos);
    j = minimal();
    j["film"] = {{"width", 0}};
    EXPECT_NE(error_of(j).find("film.width: must be in [1, 65536]"), std::string::npos);
    j = minimal();
    j["film"] = {{"width", 10.5}};
    EXPECT_NE(error_of(j).find("film.width: must be a whole number"), std::string::npos);
}

TEST(SceneLoader, NonFiniteNumbersAreRefused) {
    json j = minimal();
    j["objects"][0]["center"] = {0, std::numeric_limits<double>::infinity(), 0};
    EXPECT_EQ(error_of(j), "objects[0].center[1]: must be a finite number");
    j = minimal();
    j["camera"]["fov"] = std::nan("");
    EXPECT_EQ(error_of(j), "camera.fov: must be a finite number");
}

TEST(SceneLoader, OverridesFollowDottedPaths) {
    json j = minimal();
    apply_override(j, {"lights.0.intensity", "[5,5,5]"}, "s.json");
    apply_override(j, {"render.engine", "raster"}, "s.json");  // not JSON: a string
    apply_override(j, {"camera.fov", "30"}, "s.json");
    apply_override(j, {"render.shadow_map.bias", "0.01"}, "s.json");
    Scene s = scene_from_json(j, "s.json");
    EXPECT_EQ(std::get<PointLight>(s.lights[0]).intensity, Color(5.0f));
    EXPECT_EQ(s.render.engine, "raster");
    EXPECT_EQ(s.camera.fov_deg, 30.0f);
    EXPECT_FLOAT_EQ(s.render.shadow_map.bias, 0.01f);
    EXPECT_THROW(apply_override(j, {"lights.3.intensity", "1"}, "s.json"), Error);
    EXPECT_THROW(apply_override(j, {"camera.fov.x", "1"}, "s.json"), Error);
}

TEST(SceneLoader, TransformsComposeScaleRotateTranslate) {
    json j = minimal();
    j["objects"][0]["transform"] = {
        {"translate", {1, 2, 3}}, {"rotate", {90, 0, 0, 1}}, {"scale", 2}};
    Scene s = scene_from_json(j, "s.json");
    vec3 p = s.objects[0].transform.point(vec3(1, 0, 0));  // scale -> (2,0,0), rotate -> (0,2,0)
    EXPECT_NEAR(p.x, 1.0f, 1e-5f);
    EXPECT_NEAR(p.y, 4.0f, 1e-5f);
    EXPECT_NEAR(p.z, 3.0f, 1e-5f);
    j["objects"][0]["transform"] = {{"matrix", {1, 0, 0, 5, 0, 1, 0, 6, 0, 0, 1, 7, 0, 0, 0, 1}}};
    s = scene_from_json(j, "s.json");
    EXPECT_EQ(s.objects[0].transform.point(vec3(0.0f)), vec3(5, 6, 7));  // row-major
    j["objects"][0]["transform"] = {{"scale", {1, 0, 1}}};
    EXPECT_NE(error_of(j).find("objects[0].transform: transform is singular"), std::string::npos);
}

TEST(SceneLoader, ReadsFilesAndReportsSyntaxErrorsWithLineAndColumn) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("svetlo_loader_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::path bad = dir / "bad.json";
    { std::ofstream(bad) << "{\n  \"camera\": {\n    \"position\": [0, 1,, 5]\n  }\n}\n"; }
    try {
        load_scene(bad);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "line 3, column 23");
        EXPECT_NE(e.message().find("malformed JSON"), std::string::npos);
    }
    EXPECT_THROW(load_scene(dir / "missing.json"), Error);
}

TEST(SceneLoader, GeometryKeyNamesTheShapesAndTheirMeshFiles) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("svetlo_key_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path obj = dir / "tri.obj";
    { std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"; }
    json j = minimal();
    j["objects"].push_back({{"type", "mesh"}, {"file", "tri.obj"}, {"material", "white"}});
    const Scene a = scene_from_json(j, dir / "s.json");
    EXPECT_EQ(a.geometry_key.size(), 64u);
    // A point light and a colour move no shape.
    json lit = j;
    lit["lights"][0]["position"] = {1, 4, 0};
    lit["materials"]["white"]["albedo"] = 0.5;
    EXPECT_EQ(scene_from_json(lit, dir / "s.json").geometry_key, a.geometry_key);
    // A shape, an area light, a new material (the indices the primitives hold) do.
    json moved = j;
    moved["objects"][0]["radius"] = 2;
    EXPECT_NE(scene_from_json(moved, dir / "s.json").geometry_key, a.geometry_key);
    json area = j;
    area["lights"].push_back({{"type", "area"},
                              {"corner", {0, 3, 0}},
                              {"edge_u", {1, 0, 0}},
                              {"edge_v", {0, 0, 1}},
                              {"radiance", 1}});
    EXPECT_NE(scene_from_json(area, dir / "s.json").geometry_key, a.geometry_key);
    json more = j;
    more["materials"]["another"] = {{"type", "lambert"}, {"albedo", 0.2}};
    EXPECT_NE(scene_from_json(more, dir / "s.json").geometry_key, a.geometry_key);
    // The mesh file edited: same name, another time.
    fs::last_write_time(obj, fs::last_write_time(obj) + std::chrono::seconds(2));
    EXPECT_NE(scene_from_json(j, dir / "s.json").geometry_key, a.geometry_key);
    fs::remove_all(dir);
}

TEST(SceneLoader, CsgAndImplicitTrees) {
    json j = minimal();
    j["objects"] = json::parse(R"([
      {"type": "csg", "op": "difference", "material": "white", "transform": {"translate": [1, 0, 0]},
       "children": [
         {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1]},
         {"type": "csg", "op": "union", "children": [
           {"type": "sphere", "center": [0, 1, 0], "radius": 0.5},
           {"type": "cylinder", "base": [0, -2, 0], "axis": [0, 4, 0], "radius": 0.2}]}]},
      {"type": "implicit", "material": "white",
       "sdf": {"op": "union", "smooth": 0.2, "children": [
         {"op": "sphere", "center": [0, 0, 0], "radius": 1},
         {"op": "torus", "center": [0, 0, 0], "major_radius": 1, "minor_radius": 0.2,
          "transform": {"scale": 2}}]}}
    ])");
    Scene s = scene_from_json(j, "s.json");
    ASSERT_EQ(s.objects.size(), 2u);
    const Csg& csg = std::get<Csg>(s.objects[0].shape);
    EXPECT_EQ(csg.op, CsgOp::Difference);
    ASSERT_EQ(csg.children.size(), 2u);
    EXPECT_EQ(csg.children[0].material, 0);  // inherited from the node
    const Csg& inner = std::get<Csg>(csg.children[1].shape);
    EXPECT_EQ(inner.children.size(), 2u);
    const Implicit& imp = std::get<Implicit>(s.objects[1].shape);
    EXPECT_EQ(imp.root.op, SdfOp::Union);
    EXPECT_EQ(imp.root.smooth, 0.2f);
    EXPECT_EQ(imp.root.children[1].transform[0][0], 2.0f);
}

TEST(SceneLoader, CsgAndImplicitErrorsNameThePlace) {
    json j = minimal();
    j["objects"] =
        json::parse(R"([{"type": "csg", "op": "xor", "material": "white", "children": []}])");
    EXPECT_NE(error_of(j).find("objects[0].op: unknown value 'xor'"), std::string::npos);
    j["objects"] =
        json::parse(R"([{"type": "csg", "op": "union", "material": "white", "children": []}])");
    EXPECT_EQ(error_of(j), "objects[0].children: must be a non-empty array of objects");
    j["objects"] = json::parse(R"([{"type": "csg", "op": "union", "material": "white", "children": [
        {"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0], "edge_v": [0, 1, 0]}]}])");
    EXPECT_NE(error_of(j).find("objects[0].children[0].type: a CSG child must be a closed shape"),
              std::string::npos);
    j["objects"] = json::parse(R"([{"type": "csg", "op": "union", "children": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1}]}])");
    EXPECT_EQ(error_of(j), "objects[0].children[0].material: missing key");
    j["objects"] = json::parse(R"([{"type": "csg", "op": "union", "material": "white", "children": [
        {"type": "sphere", "center": [0, 0, 0], "radius": -1}]}])");
    EXPECT_EQ(error_of(j), "objects[0].children[0].radius: must be > 0 (is -1)");
    j["objects"] = json::parse(R"([{"type": "implicit", "material": "white",
        "sdf": {"op": "union", "children": [{"op": "blob", "radius": 1}]}}])");
    EXPECT_NE(error_of(j).find("objects[0].sdf.children[0].op: unknown value 'blob'"),
              std::string::npos);
    j["objects"] = json::parse(R"([{"type": "implicit", "material": "white",
        "sdf": {"op": "rounded_box", "min": [0, 0, 0], "max": [1, 1, 1], "radius": 0.8}}])");
    EXPECT_EQ(error_of(j), "objects[0].sdf.radius: must be at most half the smallest edge");
    j["objects"] = json::parse(R"([{"type": "implicit", "material": "white",
        "sdf": {"op": "sphere", "center": [0, 0, 0], "radius": 1, "smooth": 2}}])");
    EXPECT_NE(error_of(j).find("objects[0].sdf.smooth: unknown key"), std::string::npos);
    // Hostile nesting is refused, not recursed into without end.
    json deep = json::parse(R"({"op": "sphere", "center": [0, 0, 0], "radius": 1})");
    for (int k = 0; k < 100; ++k) deep = json{{"op", "union"}, {"children", json::array({deep})}};
    j["objects"] = json::array({json{{"type", "implicit"}, {"material", "white"}, {"sdf", deep}}});
    EXPECT_NE(error_of(j).find("nested deeper than 64"), std::string::npos);
}

}  // namespace
}  // namespace svetlo

namespace svetlo {
namespace {

/// Every name of a closed set parses to its value, and the value prints as its name.
template <class E, size_t N>
void expect_every_name_parses(const EnumName<E> (&names)[N], const std::string& section,
                              const std::string& key) {
    for (const auto& [name, value] : names) {
        EXPECT_EQ(name_of(names, value), name);
        json j = minimal();
        json& where = section == "render" ? j["render"] : j["render"][section];
        where[key] = std::string(name);
        EXPECT_EQ(error_of(j), "no error") << key << "=" << name;
    }
}

TEST(SceneLoader, ClosedSetsParseToEnumsOnceAndRefuseTypos) {
    json j = minimal();
    j["render"] = {{"shading", "gouraud"},    {"shadows", "volume"},
                   {"visibility", "painter"}, {"wireframe", "wu"},
                   {"cull", "back"},          {"shadow_map", {{"filter", "pcss"}}}};
    Scene s = scene_from_json(j, "s.json");
    EXPECT_EQ(s.render.shading, ShadingMode::Gouraud);
    EXPECT_EQ(s.render.shadows, ShadowTechnique::Volume);
    EXPECT_EQ(s.render.raster.visibility, VisibilityMethod::Painter);
    EXPECT_EQ(s.render.raster.wireframe, WireframeMode::Wu);
    EXPECT_TRUE(s.render.raster.cull_back_faces);
    EXPECT_EQ(s.render.shadow_map.filter, ShadowFilter::Pcss);
    expect_every_name_parses(kShadingModes, "render", "shading");
    expect_every_name_parses(kShadowTechniques, "render", "shadows");
    expect_every_name_parses(kVisibilityMethods, "render", "visibility");
    expect_every_name_parses(kWireframeModes, "render", "wireframe");
    expect_every_name_parses(kShadowFilters, "shadow_map", "filter");
    j = minimal();
    j["render"]["shading"] = "phnog";
    EXPECT_EQ(error_of(j),
              "render.shading: unknown value 'phnog' (expected one of: flat, gouraud, phong, "
              "depth, normal, overdraw)");
    j = minimal();
    j["render"]["shadow_map"] = {{"filter", "PCF"}};
    EXPECT_NE(error_of(j).find("render.shadow_map.filter: unknown value 'PCF'"), std::string::npos);
}

}  // namespace
}  // namespace svetlo

namespace svetlo {
namespace {

TEST(SceneLoader, ATextureIsReadOncePerFileAndColourSpace) {
    // A 2 x 2 PFM named by four colours of three materials, once through another path: one
    // texture. A fourth material asks for the file as linear data: a second (the key is the
    // file and the colour space asked for).
    std::filesystem::path dir = std::filesystem::temp_directory_path() / "svetlo_texture_once";
    std::filesystem::create_directories(dir / "sub");
    {
        std::ofstream f(dir / "t.pfm", std::ios::binary);
        f << "PF\n2 2\n-1.0\n";
        const float texels[12] = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f,
                                  0.7f, 0.8f, 0.9f, 1.0f, 0.5f, 0.25f};
        f.write(reinterpret_cast<const char*>(texels), sizeof texels);
    }
    json j = minimal();
    j["materials"] = {
        {"a", {{"type", "lambert"}, {"albedo", {{"texture", "t.pfm"}}}}},
        {"b", {{"type", "lambert"}, {"albedo", {{"texture", "sub/../t.pfm"}}}}},
        {"c", {{"type", "phong"}, {"kd", {{"texture", "t.pfm"}}}, {"ks", {{"texture", "t.pfm"}}}}},
        {"d", {{"type", "lambert"}, {"albedo", {{"texture", "t.pfm"}, {"srgb", false}}}}}};
    j["objects"][0]["material"] = "a";
    Scene s = scene_from_json(j, dir / "s.json");
    EXPECT_EQ(s.textures.size(), 2u);
    EXPECT_EQ(s.texture_sources.size(), 2u);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace svetlo
