// glTF's node hierarchy, skins and animations (glTF 2.0, 3.5, 3.7.3 and 3.11): the pose of the
// first animation's first keys, each node's transform to the file's world, and the matrices a
// skin places its mesh's vertices with at that pose (linear blend skinning).
#pragma once

#include <tiny_gltf.h>

#include <optional>
#include <vector>

#include "svetlo/core/math.h"

namespace svetlo {

/// Poses the nodes as the file's first animation begins (near what Blender's importer shows,
/// the pose 1/24 s in: docs/scene-format.md): each of its channels sets its node's translation,
/// rotation, scale or morph weights to its sampler's output at the earliest input time
/// (CUBICSPLINE's value, the middle of its triple). Channels of other paths are passed by. Throws
/// on a channel whose node, sampler or accessors are missing or do not fit, and on an animated node
/// given by a matrix.
void pose_first_keys(tinygltf::Model& model);

/// The rotation of quaternion (x, y, z, w) made unit length, as glTF stores it up to rounding
/// (a quantised one, normalised bytes or shorts, is a few parts in a thousand off and would
/// scale by the square of its length); none where it has no length or is not finite.
std::optional<mat4> unit_rotation(double x, double y, double z, double w);

/// A node's own transform: its matrix, or T R S (a rotation without a length turns nothing).
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
