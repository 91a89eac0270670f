// Radiosity's patch mesh: every triangle of the scene's triangle list is the root of a
// quadtree of midpoint subdivisions, each node split into four (its three corners' triangles
// and the middle one). Patches (the shooters of progressive refinement) are the nodes whose
// edges first fall under render.radiosity.patch_size; elements (the receivers) are the leaves,
// below element_size, split further where the light changes fast (adaptive subdivision) or
// where the hierarchical solver's links ask for it. Every node has two sides, each with its
// own radiosity: side 0 faces where the triangle's counter-clockwise normal points, side 1
// the other way (surfaces are two-sided, docs/shading.md); only an emissive
// material's front side emits.
//
// Units: radiosity B and irradiance E in W/m^2 (B = pi L on a diffuse surface), areas in m^2.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/geometry/triangle_list.h"
#include "svetlo/scene/scene.h"
#include "svetlo/shading/bsdf.h"

namespace svetlo {

/// The length of the longest edge of triangle p.
float longest_edge(const vec3 p[3]);
/// How many times a triangle with longest edge `edge` is halved to bring it under `size`.
int halvings_to(float edge, float size);
/// What of a material radiosity exchanges (docs/radiosity.md): the diffuse part of a material
/// with lobes or of an emitter, clamped to [0, 1] (a reflectance past 1 would make energy);
/// nothing for a mirror or glass.
inline Color radiosity_reflectance(const Bsdf& bsdf) {
    return bsdf.has_lobes() || bsdf.model == Bsdf::Model::Emissive
               ? glm::clamp(bsdf.diffuse, Color(0.0f), Color(1.0f))
               : Color(0.0f);
}

struct ElementNode {
    static constexpr uint32_t kNone = ~0u;

    vec3 p[3];     // corners, world space, counter-clockwise seen from the front
    vec2 bary[3];  // the corners as barycentrics (b1, b2) of the root triangle
    vec3 centroid{0.0f};
    float area = 0.0f;        // m^2
    uint32_t root = 0;        // the list's triangle this node subdivides
    uint32_t parent = kNone;  // kNone for a root
    uint32_t child = kNone;   // the first of four consecutive children, kNone for a leaf
    uint16_t level = 0;       // 0 for a root
    Color reflectance{0.0f};  // the material's diffuse part at the centroid
    Color emission{0.0f};     // pi L_e of the front side, W/m^2

    bool leaf() const { return child == kNone; }
    float longest_edge() const { return svetlo::longest_edge(p); }
};

class ElementTree {
public:
    /// The roots: one per triangle of `list`, reflectance and emission from `materials` (the
    /// list's material indices) at each node's centroid uv. Triangles without area stay
    /// leaves of no area, which nothing exchanges light with.
    ElementTree(const TriangleList& list, const std::vector<Material>& materials,
                const std::vector<TextureImage>& textures);

    const std::vector<ElementNode>& nodes() const { return nodes_; }
    const ElementNode& node(uint32_t id) const { return nodes_[id]; }
    size_t root_count() const { return root_normal_.size(); }
    /// The unit front normal of node id's root.
    vec3 normal(uint32_t id) const { return root_normal_[nodes_[id].root]; }
    /// The level under root `root` whose nodes' edges first fall under `size` (the patches'
    /// level for the patch size, the uniform elements' for the element size).
    int level_for(uint32_t root, float size) const {
        return halvings_to(nodes_[root].longest_edge(), size);
    }
    /// The side of node `id` that point q lies on: 0 in front, 1 behind.
    int side_facing(uint32_t id, vec3 q) const {
        return glm::dot(normal(id), q - nodes_[id].centroid) >= 0.0f ? 0 : 1;
    }

    /// Splits a leaf into four children (returns the first). Invalidates node references.
    uint32_t split(uint32_t id);
    /// Splits every leaf whose longest edge exceeds `size` until none does, without making
    /// more than `max_nodes` nodes in all (returns false when that limit stopped it).
    bool subdivide_to(float size, size_t max_nodes);

    /// The leaves that have area, in node order: a triangle without area (a tessellated
    /// sphere's pole) exchanges no light, and would divide 0 by 0 wherever areas weigh.
    std::vector<uint32_t> leaves() const;
    /// The node on the path from `id` to its root at `level` (or the root, or id itself).
    uint32_t ancestor_at(uint32_t id, int level) const;
    /// The leaf under root `root` (or its node at `level`, when that is above the leaf) that
    /// contains the root's barycentrics (b1, b2), and the point's barycentrics (b0, b1, b2)
    /// in that node's corners.
    uint32_t locate(uint32_t root, vec2 b, vec3& local, int level = 1 << 30) const;

    /// The point of node id at barycentrics (b1, b2) of its own corners.
    vec3 point(uint32_t id, vec2 b) const {
        const ElementNode& n = nodes_[id];
        return n.p[0] + b.x * (n.p[1] - n.p[0]) + b.y * (n.p[2] - n.p[0]);
    }

    /// The leaves as a triangle list (triangle k is leaves[k]), for the hemicube's item buffer.
    TriangleList leaf_triangles(const std::vector<uint32_t>& leaves) const;

private:
    void set_material(ElementNode& n) const;

    const TriangleList& list_;
    const std::vector<Material>& materials_;
    const std::vector<TextureImage>& textures_;
    std::vector<ElementNode> nodes_;
    std::vector<vec3> root_normal_;
};

}  // namespace svetlo
