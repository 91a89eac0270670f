#include "svetlo/scene/model_scene.h"

#include <algorithm>
#include <cmath>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"

namespace svetlo {

namespace fs = std::filesystem;

namespace {

/// A camera that frames the box [lo, hi]: fov 40 degrees, from the front (+z of the model),
/// looking down -z, far enough that the box's bounding sphere fits the film's height.
Camera framing_camera(vec3 lo, vec3 hi) {
    Camera c;
    c.fov_deg = 40.0f;
    const vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-6f);
    const float distance = radius / std::sin(radians(0.5f * c.fov_deg));
    c.look_at = centre;
    c.position = centre + vec3(0.0f, 0.0f, distance);
    c.up = vec3(0.0f, 1.0f, 0.0f);
    return c;
}

nlohmann::json camera_json(const Camera& c) {
    nlohmann::json j = {{"position", {c.position.x, c.position.y, c.position.z}},
                        {"look_at", {c.look_at.x, c.look_at.y, c.look_at.z}},
                        {"up", {c.up.x, c.up.y, c.up.z}}};
    if (c.type == Camera::Type::Orthographic) {
        j["type"] = "orthographic";
        j["height"] = c.height;
    } else {
        j["type"] = "perspective";
        j["fov"] = c.fov_deg;
    }
    return j;
}

}  // namespace

bool is_model_file(const fs::path& path) {
    const std::string ext = lower_extension(path);
    return ext == ".gltf" || ext == ".glb" || ext == ".obj" || ext == ".ply";
}

nlohmann::json default_model_light(const Camera& camera) {
    // The camera's frame: right, up, back (toward the viewer).
    const vec3 back = glm::normalize(camera.position - camera.look_at);
    const vec3 right = glm::normalize(glm::cross(camera.up, back));
    const vec3 up = glm::cross(back, right);
    const vec3 d = glm::normalize(1.0f * right - 1.5f * up - 1.0f * back);
    return {
        {"type", "directional"},
        {"direction", {d.x, d.y, d.z}},
        {"irradiance", kPi},
        {"_comment", "svetlo's default light of a model without lights (docs/scene-format.md)"}};
}

nlohmann::json model_scene_json(const fs::path& path, FileCache& meshes, const FileScope& files) {
    std::shared_ptr<const MeshFile> model;
    try {
        model = meshes.read(path, files);
    } catch (const std::exception& e) {
        throw Error(path.string(), "file", std::string("cannot read model: ") + e.what());
    }
    const Bounds3 bounds = file_bounds(*model);
    const Camera camera = model->camera ? *model->camera : framing_camera(bounds.min, bounds.max);
    nlohmann::json scene = {
        {"_comment", "the model alone (docs/scene-format.md, \"A model alone\")"},
        {"camera", camera_json(camera)},
        {"film", {{"width", 640}, {"height", 480}}},
        {"render", {{"engine", "path"}, {"spp", 64}, {"max_depth", 8}}},
        {"materials", nlohmann::json::object()},
        {"lights", nlohmann::json::array()},
        {"objects", {{{"type", "mesh"}, {"file", path.filename().string()}, {"smooth", true}}}}};
    if (model->lights.empty()) scene["lights"].push_back(default_model_light(camera));
    // A file without materials of its own (a PLY, an OBJ without MTL): a grey one.
    if (model->materials.empty()) {
        scene["materials"]["default"] = {{"type", "lambert"}, {"albedo", 0.8}};
        scene["objects"][0]["material"] = "default";
    }
    return scene;
}

}  // namespace svetlo
