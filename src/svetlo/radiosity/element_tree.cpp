#include "svetlo/radiosity/element_tree.h"

#include <algorithm>
#include <cmath>

#include "svetlo/shading/cutouts.h"

namespace svetlo {

float longest_edge(const vec3 p[3]) {
    return std::sqrt(
        std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                  glm::dot(p[0] - p[2], p[0] - p[2])}));
}

int halvings_to(float edge, float size) {
    int k = 0;
    while (edge > size && k < 30) {
        edge *= 0.5f;
        ++k;
    }
    return k;
}

ElementTree::ElementTree(const TriangleList& list, const std::vector<Material>& materials,
                         const std::vector<TextureImage>& textures)
    : list_(list), materials_(materials), textures_(textures) {
    const size_t n = list.triangle_count();
    nodes_.resize(n);
    root_normal_.resize(n);
    for (size_t t = 0; t < n; ++t) {
        ElementNode& node = nodes_[t];
        for (int c = 0; c < 3; ++c) node.p[c] = list.positions[list.indices[3 * t + c]];
        node.bary[0] = vec2(0.0f);
        node.bary[1] = vec2(1.0f, 0.0f);
        node.bary[2] = vec2(0.0f, 1.0f);
        node.root = static_cast<uint32_t>(t);
        vec3 c = glm::cross(node.p[1] - node.p[0], node.p[2] - node.p[0]);
        float len = glm::length(c);
        node.area = is_finite(c) ? 0.5f * len : 0.0f;
        root_normal_[t] = len > 0.0f && node.area > 0.0f ? c / len : vec3(0.0f, 0.0f, 1.0f);
        node.centroid = (node.p[0] + node.p[1] + node.p[2]) / 3.0f;
        set_material(node);
    }
}

void ElementTree::set_material(ElementNode& n) const {
    const vec2 b = (n.bary[0] + n.bary[1] + n.bary[2]) / 3.0f;
    const Material& material = materials_[list_.material[n.root]];
    const Varyings at = list_.varyings(n.root, b);
    Bsdf bsdf = make_bsdf(material, at, textures_);
    // An element at a cutout's hole is not there: it neither reflects nor emits (a blend's
    // coverage of both).
    const float cover = mean_cover(material.alpha, at, textures_);
    n.reflectance = cover * radiosity_reflectance(bsdf);
    n.emission = cover * kPi * bsdf.emission;  // black unless the material emits
}

uint32_t ElementTree::split(uint32_t id) {
    const uint32_t first = static_cast<uint32_t>(nodes_.size());
    ElementNode parent = nodes_[id];
    // Midpoints of the edges ab, bc, ca; the children (a, ab, ca), (ab, b, bc), (ca, bc, c)
    // and the middle (ab, bc, ca), all wound as the parent. The same midpoints of a shared
    // edge are the same floats in both triangles: (a + b) / 2 does not depend on the order.
    const vec3 m[3] = {(parent.p[0] + parent.p[1]) * 0.5f, (parent.p[1] + parent.p[2]) * 0.5f,
                       (parent.p[2] + parent.p[0]) * 0.5f};
    const vec2 mb[3] = {(parent.bary[0] + parent.bary[1]) * 0.5f,
                        (parent.bary[1] + parent.bary[2]) * 0.5f,
                        (parent.bary[2] + parent.bary[0]) * 0.5f};
    const vec3 corners[4][3] = {{parent.p[0], m[0], m[2]},
                                {m[0], parent.p[1], m[1]},
                                {m[2], m[1], parent.p[2]},
                                {m[0], m[1], m[2]}};
    const vec2 bcorners[4][3] = {{parent.bary[0], mb[0], mb[2]},
                                 {mb[0], parent.bary[1], mb[1]},
                                 {mb[2], mb[1], parent.bary[2]},
                                 {mb[0], mb[1], mb[2]}};
    for (int k = 0; k < 4; ++k) {
        ElementNode child;
        for (int c = 0; c < 3; ++c) {
            child.p[c] = corners[k][c];
            child.bary[c] = bcorners[k][c];
        }
        child.centroid = (child.p[0] + child.p[1] + child.p[2]) / 3.0f;
        child.area = 0.25f * parent.area;
        child.root = parent.root;
        child.parent = id;
        child.level = static_cast<uint16_t>(parent.level + 1);
        set_material(child);
        nodes_.push_back(child);
    }
    nodes_[id].child = first;
    return first;
}

bool ElementTree::subdivide_to(float size, size_t max_nodes) {
    // Breadth first over the node array: children are appended behind their parents.
    for (uint32_t id = 0; id < nodes_.size(); ++id) {
        if (!nodes_[id].leaf() || !(nodes_[id].area > 0.0f)) continue;
        if (nodes_[id].longest_edge() <= size) continue;
        if (nodes_.size() + 4 > max_nodes) return false;
        split(id);
    }
    return true;
}

std::vector<uint32_t> ElementTree::leaves() const {
    std::vector<uint32_t> out;
    for (uint32_t id = 0; id < nodes_.size(); ++id) {
        if (nodes_[id].leaf() && nodes_[id].area > 0.0f) out.push_back(id);
    }
    return out;
}

uint32_t ElementTree::ancestor_at(uint32_t id, int level) const {
    while (nodes_[id].level > level && nodes_[id].parent != ElementNode::kNone)
        id = nodes_[id].parent;
    return id;
}

uint32_t ElementTree::locate(uint32_t root, vec2 b, vec3& local, int level) const {
    vec3 u(1.0f - b.x - b.y, b.x, b.y);
    uint32_t id = root;
    while (!nodes_[id].leaf() && nodes_[id].level < level) {
        // In the node's own barycentrics (ua, ub, uc): the corner children hold the points
        // with one coordinate past 1/2, the middle one the rest (element_tree.h).
        uint32_t c = nodes_[id].child;
        if (u.x >= 0.5f) {
            id = c;
            u = vec3(2.0f * u.x - 1.0f, 2.0f * u.y, 2.0f * u.z);
        } else if (u.y >= 0.5f) {
            id = c + 1;
            u = vec3(2.0f * u.x, 2.0f * u.y - 1.0f, 2.0f * u.z);
        } else if (u.z >= 0.5f) {
            id = c + 2;
            u = vec3(2.0f * u.x, 2.0f * u.y, 2.0f * u.z - 1.0f);
        } else {
            id = c + 3;
            u = vec3(1.0f - 2.0f * u.z, 1.0f - 2.0f * u.x, 1.0f - 2.0f * u.y);
        }
    }
    local = u;
    return id;
}

TriangleList ElementTree::leaf_triangles(const std::vector<uint32_t>& leaves) const {
    TriangleList out;
    out.positions.reserve(3 * leaves.size());
    for (uint32_t id : leaves) {
        for (int c = 0; c < 3; ++c) {
            out.indices.push_back(static_cast<uint32_t>(out.positions.size()));
            out.positions.push_back(nodes_[id].p[c]);
            out.normals.push_back(vec3(0.0f));
            out.uvs.push_back(vec2(0.0f));
        }
        out.material.push_back(list_.material[nodes_[id].root]);
    }
    out.objects.push_back(PrimitiveRange{0, static_cast<uint32_t>(leaves.size())});
    return out;
}

}  // namespace svetlo
