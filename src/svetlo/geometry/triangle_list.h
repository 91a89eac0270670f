// The scene as one list of world-space triangles, built once per render: what the rasterizer
// draws, and what shadow volumes (silhouette edges) and radiosity meshing read. Every object
// is tessellated (tessellate.h) in its own space and then placed by its transform, so that
// the ray tracer and the rasterizer see the same surfaces.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/geometry/tessellate.h"

namespace svetlo {

struct TriangleList {
    static constexpr uint32_t kOpen = ~0u;  // no neighbour across an edge

    std::vector<vec3> positions;          // world space
    std::vector<vec3> normals;            // per vertex: unit, or zero where there is none
    std::vector<vec2> uvs;                // per vertex
    std::vector<vec2> uvs1;               // empty, or per vertex (Mesh::uvs1; uvs where none)
    std::vector<vec4> colors;             // empty, or per vertex (Mesh::colors; white where none)
    std::vector<vec4> tangents;           // per vertex (Mesh::tangents), zero where none
    std::vector<uint32_t> indices;        // 3 per triangle, counter-clockwise seen from its front
    std::vector<uint32_t> material;       // per triangle, an index into the scene's materials
    std::vector<PrimitiveRange> objects;  // per object: its triangles [first, end)
    std::vector<char> convex;             // per object: 1 where tessellates_convex, else 0
    std::vector<vec3> centroid;           // per object: the mean of its triangles' corners
    /// Edge adjacency (build_adjacency): for edge e of triangle t, from its vertex e to vertex
    /// e + 1, neighbour[3 t + e] is the triangle across it, or kOpen.
    std::vector<uint32_t> neighbour;
    /// Homogeneous weight per vertex, or empty for 1 everywhere: a vertex of weight 0 is the
    /// point at infinity in the direction positions[v] (a shadow volume's extrusion).
    std::vector<float> w;

    size_t triangle_count() const { return material.size(); }
    /// What the materials' colours read at barycentric point b (of corners 1 and 2) of
    /// triangle t.
    Varyings varyings(size_t t, vec2 b) const {
        return interpolate_varyings(uvs, uvs1, colors, &indices[3 * t], b);
    }
    /// The bounds of the positions (of a list whose vertices all have weight 1).
    Bounds3 bounds() const {
        Bounds3 b;
        for (vec3 p : positions) b.extend(p);
        return b;
    }
};

/// Whether a ray that leaves point p of an object's surface from its side of normal n, away
/// from that side, meets none of the object's triangles: the object tessellates convex
/// (TriangleList::convex, tessellates_convex) and its centroid (strictly inside a solid, in
/// the plane of a flat one) is not in front of that side. Then every triangle of the object
/// lies behind or in the plane the ray leaves, and the ray moves away from it. (Else, the
/// inside of a solid seen, it may meet them.)
inline bool leaves_convex(bool convex, vec3 centroid, vec3 p, vec3 n) {
    return convex && glm::dot(n, centroid - p) <= 0.0f;
}

/// The list's triangles as ray-traceable geometry (positions, indices and materials), for a
/// BVH over exactly what was drawn: the rasterizer's ray-traced shadows, radiosity's
/// visibility.
inline Geometry triangle_geometry(const TriangleList& list) {
    Geometry g;
    g.positions = list.positions;
    g.uvs = list.uvs;  // what alpha's holes read (cutouts.h)
    g.uvs1 = list.uvs1;
    g.colors = list.colors;
    g.indices = list.indices;
    g.triangle_material = list.material;
    return g;
}

/// Every object tessellated in its own space (its transform not applied), `threads` objects in
/// parallel; a shape's tessellation is given tangents from its uvs. place_mesh places them.
std::vector<Mesh> local_meshes(const std::vector<const Object*>& objects,
                               const TessellationOptions& options, int threads);

/// Sizes every per-vertex and per-triangle array of `list` (uvs1 and colors only when asked).
void size_list(TriangleList& list, size_t vertices, size_t triangles, bool second_set,
               bool colored);

/// Vertex v of mesh `m` placed by `transform` (`nm`: normal_matrix of its matrix) into vertex
/// `to` of `list`, as place_mesh places every vertex.
inline void place_vertex(const Mesh& m, size_t v, const Transform& transform, const mat3& nm,
                         TriangleList& list, size_t to) {
    list.positions[to] = vec3(transform.matrix * vec4(m.positions[v], 1.0f));
    const vec3 n = nm * (v < m.normals.size() ? m.normals[v] : vec3(0.0f));
    const float len2 = glm::dot(n, n);
    list.normals[to] = len2 > 0.0f ? n * (1.0f / std::sqrt(len2)) : vec3(0.0f);
    list.uvs[to] = v < m.uvs.size() ? m.uvs[v] : vec2(0.0f);
    if (!list.uvs1.empty()) list.uvs1[to] = v < m.uvs1.size() ? m.uvs1[v] : list.uvs[to];
    if (!list.colors.empty()) list.colors[to] = v < m.colors.size() ? m.colors[v] : vec4(1.0f);
    list.tangents[to] =
        v < m.tangents.size() ? transform_tangent(transform, m.tangents[v]) : vec4(0.0f);
}

/// Writes mesh `m` (one of local_meshes's), placed by `transform`, into `list` (sized by
/// size_list) from vertex `first_vertex` and triangle `first_triangle`: positions by the
/// transform, normals by its inverse transpose made unit, tangents as vectors of the surface;
/// uvs1 and colours where the list has them (uvs and white where the mesh has none). Each
/// triangle's material is `material`, or the mesh's own where it is negative.
void place_mesh(const Mesh& m, const Transform& transform, int material, TriangleList& list,
                size_t first_vertex, size_t first_triangle);

/// Tessellates and places every object, in order (one range each in `objects`); `threads`
/// tessellate objects in parallel. Normals are carried by the inverse transpose and made unit.
TriangleList build_triangle_list(const std::vector<const Object*>& objects,
                                 const TessellationOptions& options, int threads);

/// Fills `neighbour`. Vertices are welded by exact position first (a mesh's seams, where uvs
/// or normals differ, still join). An edge joins two triangles when exactly two use it, in
/// opposite directions (a consistently wound 2-manifold); an edge of one triangle (a hole, a
/// quad's border), of more than two, or of two wound the same way is open. Triangles with two
/// welded vertices alike have no area and no neighbours.
void build_adjacency(TriangleList& list);

/// Per object of a list with adjacency (build_adjacency): 1 where it is closed, every edge of
/// its triangles joined. A triangle with two vertices alike (a sphere's pole row) has no area
/// and no neighbours: it leaves its object closed.
std::vector<char> closed_objects(const TriangleList& list);

}  // namespace svetlo
