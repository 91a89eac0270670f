#include "svetlo/geometry/triangle_list.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>

#include "svetlo/core/parallel.h"

namespace svetlo {

TriangleList build_triangle_list(const std::vector<const Object*>& objects,
                                 const TessellationOptions& options, int threads) {
    std::vector<Mesh> meshes(objects.size());
    parallel_indices(objects.size(), threads, [&](size_t k) {
        Object local = *objects[k];
        local.transform = Transform{};
        meshes[k] = tessellate(local, options);
    });
    TriangleList list;
    size_t vertices = 0, triangles = 0;
    for (const Mesh& m : meshes) {
        vertices += m.positions.size();
        triangles += m.triangle_count();
    }
    list.positions.resize(vertices);
    list.normals.resize(vertices);
    list.uvs.resize(vertices);
    list.indices.resize(3 * triangles);
    list.material.resize(triangles);
    list.objects.resize(objects.size());
    std::vector<size_t> first_vertex(objects.size()), first_triangle(objects.size());
    for (size_t k = 0, v = 0, t = 0; k < objects.size(); ++k) {
        first_vertex[k] = v;
        first_triangle[k] = t;
        list.objects[k] = {static_cast<uint32_t>(t),
                           static_cast<uint32_t>(t + meshes[k].triangle_count())};
        v += meshes[k].positions.size();
        t += meshes[k].triangle_count();
    }
    parallel_indices(objects.size(), threads, [&](size_t k) {
        const Mesh& m = meshes[k];
        const mat4& model = objects[k]->transform.matrix;
        const mat3 nm = normal_matrix(model);
        const size_t base = first_vertex[k];
        for (size_t v = 0; v < m.positions.size(); ++v) {
            list.positions[base + v] = vec3(model * vec4(m.positions[v], 1.0f));
            vec3 n = nm * (v < m.normals.size() ? m.normals[v] : vec3(0.0f));
            float len2 = glm::dot(n, n);
            list.normals[base + v] = len2 > 0.0f ? n * (1.0f / std::sqrt(len2)) : vec3(0.0f);
            list.uvs[base + v] = v < m.uvs.size() ? m.uvs[v] : vec2(0.0f);
        }
        for (size_t t = 0; t < m.triangle_count(); ++t) {
            for (int c = 0; c < 3; ++c) {
                list.indices[3 * (first_triangle[k] + t) + c] =
                    static_cast<uint32_t>(base + m.indices[3 * t + c]);
            }
            list.material[first_triangle[k] + t] = static_cast<uint32_t>(m.face_material[t]);
        }
    });
    return list;
}

namespace {

struct PositionHash {
    size_t operator()(const vec3& p) const {
        uint32_t b[3];
        std::memcpy(b, &p, sizeof(b));
        return (b[0] * 73856093u) ^ (b[1] * 19349663u) ^ (b[2] * 83492791u);
    }
};

}  // namespace

void build_adjacency(TriangleList& list) {
    // Weld: one id per distinct position.
    std::unordered_map<vec3, uint32_t, PositionHash> ids;
    std::vector<uint32_t> weld(list.positions.size());
    for (size_t v = 0; v < list.positions.size(); ++v) {
        vec3 p = list.positions[v] + vec3(0.0f);  // -0 and +0 are one position
        weld[v] = ids.try_emplace(p, static_cast<uint32_t>(ids.size())).first->second;
    }
    // Every directed edge, sorted by its undirected key: a manifold edge is a pair of
    // neighbours in this order, wound opposite ways.
    struct Edge {
        uint64_t key;
        uint32_t slot;  // 3 t + e
        bool forward;   // from the lower welded id to the higher
    };
    const size_t count = list.triangle_count();
    std::vector<Edge> edges;
    edges.reserve(3 * count);
    for (size_t t = 0; t < count; ++t) {
        uint32_t w[3] = {weld[list.indices[3 * t]], weld[list.indices[3 * t + 1]],
                         weld[list.indices[3 * t + 2]]};
        // A triangle with two vertices alike (a sphere's pole row, a cone's apex) has no area
        // and joins nothing: its neighbours join each other across it.
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
        for (int e = 0; e < 3; ++e) {
            uint32_t a = w[e], b = w[(e + 1) % 3];
            uint64_t key = (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            edges.push_back({key, static_cast<uint32_t>(3 * t + e), a < b});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
        return x.key != y.key ? x.key < y.key : x.slot < y.slot;
    });
    list.neighbour.assign(3 * count, TriangleList::kOpen);
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        if (j - i == 2 && edges[i].forward != edges[i + 1].forward) {
            list.neighbour[edges[i].slot] = edges[i + 1].slot / 3;
            list.neighbour[edges[i + 1].slot] = edges[i].slot / 3;
        }
        i = j;
    }
}

}  // namespace svetlo
