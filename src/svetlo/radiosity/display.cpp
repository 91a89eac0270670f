#include "svetlo/radiosity/display.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "svetlo/core/bit_cast.h"

namespace svetlo {

namespace {

/// A corner's exact position as a key: midpoints are computed alike on both sides of an
/// edge (element_tree.cpp), so shared corners are bit-identical.
struct PositionKey {
    uint32_t x, y, z;
    bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
    size_t operator()(const PositionKey& k) const {
        uint64_t h = (uint64_t{k.x} * 0x9e3779b97f4a7c15ULL) ^
                     (uint64_t{k.y} * 0xc2b2ae3d27d4eb4fULL) ^
                     (uint64_t{k.z} * 0x165667b19e3779f9ULL);
        return static_cast<size_t>(h ^ (h >> 29));
    }
};
PositionKey key_of(vec3 p) {
    // +0 and -0 are one position.
    return {svetlo::bit_cast<uint32_t>(p.x + 0.0f), svetlo::bit_cast<uint32_t>(p.y + 0.0f),
            svetlo::bit_cast<uint32_t>(p.z + 0.0f)};
}

constexpr float kSmooth = 0.8f;  // cos 37 degrees: corners of normals closer than this are one

}  // namespace

IrradianceField::IrradianceField(const ElementTree& tree, const std::vector<Sides>& total,
                                 const std::vector<Sides>& indirect)
    : tree_(tree), corner_of_(3 * tree.nodes().size(), ~0u) {
    std::unordered_map<PositionKey, std::vector<uint32_t>, PositionHash> at;
    auto find = [&](vec3 p, vec3 n, bool make) -> uint32_t {
        auto it = at.find(key_of(p));
        if (it != at.end()) {
            for (uint32_t c : it->second)
                if (glm::dot(corners_[c].normal, n) >= kSmooth) return c;
        }
        if (!make) return ~0u;
        uint32_t id = static_cast<uint32_t>(corners_.size());
        corners_.push_back(Corner{n, {}, 0.0f});
        at[key_of(p)].push_back(id);
        return id;
    };
    std::vector<uint32_t> leaves = tree.leaves();
    for (uint32_t id : leaves) {
        const ElementNode& e = tree.node(id);
        for (int c = 0; c < 3; ++c) {
            uint32_t k = find(e.p[c], tree.normal(id), true);
            corner_of_[3 * id + c] = k;
            Corner& corner = corners_[k];
            for (int s = 0; s < 2; ++s) {
                corner.value[s] += e.area * total[id].v[s];
                corner.value[2 + s] += e.area * indirect[id].v[s];
            }
            corner.weight += e.area;
        }
    }
    for (Corner& c : corners_)
        for (Color& v : c.value) v /= c.weight;

    // T-vertices: coarse leaves first, each edge's midpoints (recursively) take the edge's
    // linear interpolation, so both sides of the edge shade alike.
    std::stable_sort(leaves.begin(), leaves.end(),
                     [&](uint32_t a, uint32_t b) { return tree.node(a).area > tree.node(b).area; });
    auto anchor = [&](auto&& self, vec3 a, vec3 b, uint32_t ca, uint32_t cb, vec3 n,
                      int depth) -> void {
        if (depth > 16) return;
        vec3 m = (a + b) * 0.5f;
        uint32_t cm = find(m, n, false);
        if (cm == ~0u) return;
        for (int v = 0; v < 4; ++v)
            corners_[cm].value[v] = 0.5f * (corners_[ca].value[v] + corners_[cb].value[v]);
        self(self, a, m, ca, cm, n, depth + 1);
        self(self, m, b, cm, cb, n, depth + 1);
    };
    for (uint32_t id : leaves) {
        const ElementNode& e = tree.node(id);
        for (int c = 0; c < 3; ++c) {
            int d = (c + 1) % 3;
            anchor(anchor, e.p[c], e.p[d], corner_of_[3 * id + c], corner_of_[3 * id + d],
                   tree.normal(id), 0);
        }
    }
}

IrradianceField::Value IrradianceField::at(uint32_t root, vec2 b, int side) const {
    vec3 local;
    uint32_t leaf = tree_.locate(root, b, local);
    Value v;
    for (int c = 0; c < 3; ++c) {
        uint32_t k = corner_of_[3 * leaf + c];
        if (k == ~0u) continue;
        v.total += local[c] * corners_[k].value[side];
        v.indirect += local[c] * corners_[k].value[2 + side];
    }
    return v;
}

DisplaySample sample_on_triangle(const TriangleList& list, uint32_t t, vec3 ng, const Ray& ray) {
    const uint32_t* tri = &list.indices[3 * static_cast<size_t>(t)];
    const vec3 p0 = list.positions[tri[0]], p1 = list.positions[tri[1]],
               p2 = list.positions[tri[2]];
    DisplaySample out;
    const float denom = glm::dot(ng, ray.d);
    const float t_hit = std::abs(denom) > 1e-20f ? glm::dot(ng, p0 - ray.o) / denom : 0.0f;
    // Barycentrics of the point on the plane, by the normal equations of its two edges.
    const vec3 e1 = p1 - p0, e2 = p2 - p0, q = ray.o + t_hit * ray.d - p0;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float det = d11 * d22 - d12 * d12;
    vec2 b(0.0f);
    if (std::abs(det) > 0.0f) {
        const float q1 = glm::dot(q, e1), q2 = glm::dot(q, e2);
        b = vec2((d22 * q1 - d12 * q2) / det, (d11 * q2 - d12 * q1) / det);
    }
    b = glm::clamp(b, vec2(0.0f), vec2(1.0f));
    if (b.x + b.y > 1.0f) b /= b.x + b.y;
    out.b = b;
    out.x = p0 + b.x * e1 + b.y * e2;
    out.side = denom < 0.0f ? 0 : 1;
    out.n = out.side == 0 ? ng : -ng;
    out.at = list.varyings(t, b);
    out.distance = t_hit * glm::length(ray.d);
    return out;
}

Color patches_view(const ElementTree& tree, uint32_t t, vec2 b, int side,
                   const std::vector<Sides>& E, Color rho, float patch_size, float footprint) {
    vec3 local, plocal;
    const uint32_t leaf = tree.locate(t, b, local);
    const uint32_t patch = tree.locate(t, b, plocal, tree.level_for(t, patch_size));
    // Near an edge: the smallest barycentric times the triangle's height is within half the
    // footprint.
    auto near_edge = [&](vec3 u, uint32_t node) {
        const float height = std::sqrt(2.0f * tree.node(node).area);
        return std::min({u.x, u.y, u.z}) * height < 0.5f * footprint;
    };
    const Color value = rho * (1.0f / kPi) * E[leaf].v[side];
    if (near_edge(plocal, patch)) return Color(1.0f, 0.1f, 0.05f);
    if (near_edge(local, leaf)) return 0.3f * value + Color(0.0f, 0.02f, 0.05f);
    return value;
}

}  // namespace svetlo
