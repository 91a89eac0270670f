// The parts of the scene loader, one per section of the file. Internal to scene/.
#pragma once

#include <map>
#include <optional>

#include "svetlo/core/image_io.h"
#include "svetlo/scene/file_cache.h"
#include "svetlo/scene/json_node.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

Camera parse_camera(const JsonNode& node);
Film parse_film(const JsonNode& node);
RenderSettings parse_render(const JsonNode& node);
void parse_materials(const JsonNode& node, Scene& scene, FileCache& files);
/// The file that `node` (a string) names, from the scene file's folder and inside the scene's
/// FileScope; fails naming the node otherwise.
std::filesystem::path named_file(const JsonNode& node, const Scene& scene);
/// What the scene's textures may still take (kMaxSceneTextureBytes less what they take).
size_t texture_bytes_left(const Scene& scene);

/// A material colour (constant, texture or checker); textures are loaded into the scene.
/// A material colour (constant, texture or checker); an image is sRGB unless `srgb_default` is
/// false or the texture says otherwise ("srgb": false).
ColorSource parse_color_source(const JsonNode& node, Scene& scene, FileCache& files,
                               bool srgb_default = true);
/// An image texture {"texture": IMAGE, "filter", "wrap", ...} read as `meaning` says.
ColorSource parse_image_source(const JsonNode& node, Scene& scene, FileCache& files,
                               TexelMeaning meaning);
/// One material: its model's keys, and the keys of every material (emission).
Material parse_material(const JsonNode& node, Scene& scene, FileCache& files);
Light parse_light(const JsonNode& node);
/// The top-level `environment`: the map read into the scene's textures.
void parse_environment(const JsonNode& node, Scene& scene, FileCache& files);
Transform parse_transform(const JsonNode& node);

/// The top-level `prototypes` (docs/scene-format.md, "Instances"): each parsed the first
/// time an instance names it, with the lights its mesh files bring; a prototype that holds
/// an instance of itself, directly or through others, is refused naming the chain.
class Prototypes {
public:
    explicit Prototypes(std::optional<JsonNode> section);

    struct Parts {
        /// Where the prototype's objects lie, in its space: its own (a Scene::prototypes
        /// entry, when it has any), then those of the prototypes it places.
        std::vector<Instance> placements;
        std::vector<Light> lights;
    };
    /// The parts of the prototype that `name` (an instance's "prototype" key) names.
    const Parts& get(const JsonNode& name, Scene& scene, FileCache& meshes);

    /// Placements made so far (bounded: docs/scene-format.md, "Instances").
    size_t placed = 0;

private:
    std::optional<JsonNode> section_;
    std::map<std::string, Parts> parsed_;
    std::vector<std::string> expanding_;  // the chain being parsed, outermost first
};

/// An entry of `objects` (or of a prototype's): its object appended to `out`, or an
/// instance's placements (nested prototypes resolved) to `placed`.
void parse_object(const JsonNode& node, Scene& scene, FileCache& meshes, Prototypes& prototypes,
                  std::vector<Object>& out, std::vector<Instance>& placed);

/// The top level's placements into the scene: each into Scene::instances, or written into
/// Scene::objects as copies where its prototype emits or holds a plane (scene.h).
void settle_instances(std::vector<Instance> placed, Scene& scene);

}  // namespace svetlo
