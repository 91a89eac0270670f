// The parts of the scene loader, one per section of the file. Internal to scene/.
#pragma once

#include "svetlo/scene/json_node.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

Camera parse_camera(const JsonNode& node);
Film parse_film(const JsonNode& node);
RenderSettings parse_render(const JsonNode& node);
void parse_materials(const JsonNode& node, Scene& scene);
/// The file that `node` (a string) names, from the scene file's folder and inside the scene's
/// FileScope; fails naming the node otherwise.
std::filesystem::path named_file(const JsonNode& node, const Scene& scene);
/// What the scene's textures may still take (kMaxSceneTextureBytes less what they take).
size_t texture_bytes_left(const Scene& scene);

/// A material colour (constant, texture or checker); textures are loaded into the scene.
/// A material colour (constant, texture or checker); an image is sRGB unless `srgb_default` is
/// false or the texture says otherwise ("srgb": false).
ColorSource parse_color_source(const JsonNode& node, Scene& scene, bool srgb_default = true);
/// One material: its model's keys, and the keys of every material (emission).
Material parse_material(const JsonNode& node, Scene& scene);
Light parse_light(const JsonNode& node);
/// The top-level `environment`: the map read into the scene's textures.
void parse_environment(const JsonNode& node, Scene& scene);
Transform parse_transform(const JsonNode& node);
void parse_object(const JsonNode& node, Scene& scene, MeshFileCache& meshes);

}  // namespace svetlo
