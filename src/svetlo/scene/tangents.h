// Per-vertex tangents for normal mapping, made as MikkTSpace makes them (Mikkelsen 2008,
// "Simulation of wrinkled surfaces revisited", the tangent space glTF and Blender bake normal
// maps in): each triangle's tangent and bitangent from its texture coordinates' gradients,
// projected onto the vertex normal's plane and summed with the triangle's angle at the
// vertex as weight; the tangent then made orthogonal to the normal, the bitangent kept as a
// sign. Unlike MikkTSpace, vertices are not split where their triangles disagree in
// handedness (a mirrored uv island shares no vertex with its twin in glTF and OBJ files,
// whose vertices are already split at uv seams). docs/real-scenes.md, "Normal maps".
#pragma once

#include <vector>

#include "svetlo/scene/scene.h"

namespace svetlo {

/// One tangent per position of `mesh` (Mesh::tangents' convention): xyz unit, w = +-1, or
/// zero where no triangle with distinct texture coordinates meets the vertex. Needs uvs;
/// without normals the triangles' own normals are summed. Empty when the mesh has no uvs.
std::vector<vec4> mesh_tangents(const Mesh& mesh);

/// Gives every mesh object of `scene` whose material (or one of its faces' materials) has a
/// normal map, and whose file gave no tangents, the tangents mesh_tangents makes.
void add_missing_tangents(Scene& scene);

/// The tangent of the surface at a hit: the interpolated vertex tangent `t` made orthogonal to
/// the unit shading normal `ns`, and its sign; zero when `t` is (nearly) along `ns`.
vec4 orthogonal_tangent(vec4 t, vec3 ns);

}  // namespace svetlo
