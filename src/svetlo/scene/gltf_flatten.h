// What a glTF model's nodes place, made into svetlo's meshes (docs/scene-format.md, "Mesh
// files"): every triangle primitive (lists, strips, fans) of the default scene's node trees,
// node transforms baked in where one node places a mesh, kept as instances where several do
// (or EXT_mesh_gpu_instancing does); morph targets at the file's weights, skins at the nodes'
// pose (gltf_nodes.h); KHR_lights_punctual lights (glTF's candela and lux taken as W/sr and
// W/m^2, since svetlo is radiometric) and the first camera.
#pragma once

#include <tiny_gltf.h>

#include "svetlo/scene/mesh_file.h"

namespace svetlo {

/// Appends to `file` (its materials already read, in the file's order) the meshes, lights
/// and camera that the default scene's nodes place, or, without a scene, every tree of nodes
/// from its root. Throws with one line for what the file gets wrong.
void place_gltf_nodes(const tinygltf::Model& model, MeshFile& file);

}  // namespace svetlo
