// A model file where a scene is expected (docs/scene-format.md, "A model alone"): the framing
// camera, the file's own camera, the default light and the file's own lights.
#include "svetlo/scene/model_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "svetlo/core/error.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;

fs::path data(const std::string& name) { return fs::path(SVETLO_TEST_DATA) / name; }

vec3 v3(const nlohmann::json& j) {
    return vec3(j[0].get<float>(), j[1].get<float>(), j[2].get<float>());
}

TEST(ModelScene, ModelExtensionsInAnyCase) {
    for (const char* name : {"a.gltf", "a.GLB", "b.obj", "c.Ply"})
        EXPECT_TRUE(is_model_file(name)) << name;
    for (const char* name : {"a.json", "a.png", "gltf", "a.gltf.txt"})
        EXPECT_FALSE(is_model_file(name)) << name;
}

TEST(ModelScene, AModelWithoutCameraIsFramedFromTheFrontWithTheDefaultLight) {
    FileCache meshes;
    const fs::path model = data("tetra_part.obj");
    const nlohmann::json j = model_scene_json(model, meshes);
    // The bounds' centre straight ahead down -z, the bounding sphere inside the 40 degree fov.
    const MeshFile& file = *meshes.read(model);
    vec3 lo(kInfinity), hi(-kInfinity);
    for (vec3 p : file.mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const vec3 centre = 0.5f * (lo + hi), eye = v3(j["camera"]["position"]);
    EXPECT_EQ(j["camera"]["fov"].get<float>(), 40.0f);
    EXPECT_NEAR(glm::distance(v3(j["camera"]["look_at"]), centre), 0.0f, 1e-5f);
    EXPECT_NEAR(eye.x, centre.x, 1e-5f);
    EXPECT_NEAR(eye.y, centre.y, 1e-5f);
    EXPECT_GT(eye.z, hi.z);
    const float radius = 0.5f * glm::length(hi - lo);
    EXPECT_NEAR(std::asin(radius / glm::distance(eye, centre)), radians(20.0f), 1e-4f);
    // No light in the file: the default one, pi W/m^2 from above the viewer's left shoulder.
    ASSERT_EQ(j["lights"].size(), 1u);
    EXPECT_EQ(j["lights"][0]["type"], "directional");
    EXPECT_FLOAT_EQ(j["lights"][0]["irradiance"].get<float>(), kPi);
    const vec3 d = v3(j["lights"][0]["direction"]);
    EXPECT_GT(
        d.x,
        0.0f);  // travels right, down and away: it comes from the upper left, behind the viewer
    EXPECT_LT(d.y, 0.0f);
    EXPECT_LT(d.z, 0.0f);
    EXPECT_EQ(j["objects"][0]["file"], "tetra_part.obj");
    // The JSON is a scene as any other: it loads, and names the model relative to itself.
    const Scene scene = scene_from_json(j, model, &meshes);
    EXPECT_EQ(scene.objects.size(), 1u);
}

TEST(ModelScene, AGltfBringsItsOwnCameraAndLights) {
    const fs::path dir = fs::temp_directory_path() / "svetlo_model_scene_test";
    fs::create_directories(dir);
    // A triangle, a camera at (0, 0, 3) turned 90 degrees about +y (so looking down -x), and a
    // point light.
    std::ifstream in(data("triangle.gltf"));
    nlohmann::json g = nlohmann::json::parse(in);
    const float s = std::sqrt(0.5f);
    g["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    g["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 3}}, {"rotation", {0, s, 0, s}}});
    g["scenes"][0]["nodes"].push_back(g["nodes"].size() - 1);
    std::ofstream(dir / "camera.gltf") << g.dump();
    FileCache meshes;
    const nlohmann::json j = model_scene_json(dir / "camera.gltf", meshes);
    EXPECT_NEAR(j["camera"]["fov"].get<float>(), 0.5f * 180.0f / kPi, 1e-4f);
    EXPECT_NEAR(glm::distance(v3(j["camera"]["position"]), vec3(0, 0, 3)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(v3(j["camera"]["look_at"]), vec3(-1, 0, 3)), 0.0f, 1e-5f);
    EXPECT_TRUE(j["lights"].empty());  // the file's point light comes with the mesh object
    const Scene scene = scene_from_json(j, dir / "camera.gltf", &meshes);
    EXPECT_EQ(scene.lights.size(), 1u);
    fs::remove_all(dir);
}

TEST(ModelScene, AModelThatCannotBeReadNamesItsFile) {
    FileCache meshes;
    try {
        model_scene_json(data("broken.gltf"), meshes);
        ADD_FAILURE() << "read";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), data("broken.gltf").string());
        EXPECT_EQ(e.where(), "file");
    }
    EXPECT_THROW(effective_scene_json(data("no_such_model.glb"), {}), Error);
}

}  // namespace
}  // namespace svetlo
