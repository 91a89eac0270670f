// A model file given where a scene is expected is a scene (docs/scene-format.md, "A model
// alone"): the model as one mesh object (with a grey Lambert material when the file has no
// materials), the file's own camera or one that frames its bounds, the file's own lights or
// svetlo's default light. The scene is written as JSON, the same
// JSON a scene file holds, so that overrides, provenance and `svetlo reproduce` treat it as
// any other.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "svetlo/scene/file_cache.h"
#include "svetlo/scene/mesh_file.h"

namespace svetlo {

/// True for the extensions of the model files svetlo reads (.gltf, .glb, .obj, .ply, any case).
bool is_model_file(const std::filesystem::path& path);

/// The scene of the model `path` (read through `meshes`, which the render then shares).
/// Throws Error naming the file for one that cannot be read.
nlohmann::json model_scene_json(const std::filesystem::path& path, FileCache& meshes,
                                const FileScope& files = {});

/// The default light of a model without lights of its own: a directional light from above
/// the viewer's left shoulder (it travels along (1, -1.5, -1), normalised, in the camera's
/// frame), of irradiance pi W/m^2, so that a white Lambertian surface facing it has radiance 1.
nlohmann::json default_model_light(const Camera& camera);

}  // namespace svetlo
