// glTF's metallic-roughness materials as svetlo's cook_torrance (docs/scene-format.md, "Mesh
// files"): base colour, metallic-roughness, occlusion, emissive and normal textures with their
// samplers, coordinate sets and KHR_texture_transform; alphaMode; KHR_materials_ior,
// _transmission, _volume, _clearcoat and _emissive_strength; EXT_texture_webp's images.
#pragma once

#include <map>
#include <string>

#include "svetlo/scene/mesh_file.h"

namespace tinygltf {
class Model;
}

namespace svetlo {

/// Whether a URI names a resource on a network (a scheme before "://"): svetlo reads local
/// files and data: URIs only, and makes no request.
inline bool names_network(const std::string& uri) { return uri.find("://") != std::string::npos; }
inline constexpr const char* kNetwork =
    "names a network resource (svetlo reads local files and data: URIs only)";

/// The images whose files the glTF reader left for the threads that decode them: image index
/// -> the file (checked already: inside the model's folder, a regular file of bounded size).
/// The other images hold their encoded bytes.
using GltfImageFiles = std::map<int, std::string>;

/// Every material of `model` into file.materials and file.material_names, the images they
/// use read (`image_files`) and decoded into file.textures (once per colour space), on all
/// cores. Throws std::runtime_error naming the material, the slot and the texture or image
/// that is missing, bad or does not decode.
void read_gltf_materials(const tinygltf::Model& model, const GltfImageFiles& image_files,
                         MeshFile& file);

}  // namespace svetlo
