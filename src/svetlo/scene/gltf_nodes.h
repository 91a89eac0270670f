// glTF's node hierarchy and skins (glTF 2.0, 3.5 and 3.7.3): each node's transform to the
// file's world, and the matrices a skin places its mesh's vertices with, at the pose the
// nodes' transforms give (linear blend skinning; animations are not read).
#pragma once

#include <tiny_gltf.h>

#include <vector>

#include "svetlo/core/math.h"

namespace svetlo {

/// A node's own transform: its matrix, or T R S.
mat4 node_matrix(const tinygltf::Node& node);

/// Every node's transform to the file's world: its parents' times its own. Throws where the
/// nodes do not form trees (a node with two parents, a cycle, a child that is no node).
std::vector<mat4> node_world_matrices(const tinygltf::Model& model);

/// The matrix skin `skin` places each of `prim`'s `count` vertices with: the sum over the
/// vertex's joints (JOINTS_0 and WEIGHTS_0, and JOINTS_1 and WEIGHTS_1 where given) of its
/// weight times the joint's world transform (`world`, node_world_matrices) times its inverse
/// bind matrix, the weights scaled to sum to one. Empty where the primitive has no JOINTS_0.
std::vector<mat4> skinning_matrices(const tinygltf::Model& model, int skin,
                                    const tinygltf::Primitive& prim, size_t count,
                                    const std::vector<mat4>& world);

}  // namespace svetlo
