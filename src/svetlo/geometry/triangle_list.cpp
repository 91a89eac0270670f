#include "svetlo/geometry/triangle_list.h"

#include <algorithm>
#include <cstring>

#include "svetlo/core/parallel.h"
#include "svetlo/scene/tangents.h"

namespace svetlo {

std::vector<Mesh> local_meshes(const std::vector<const Object*>& objects,
                               const TessellationOptions& options, int threads) {
    std::vector<Mesh> meshes(objects.size());
    parallel_indices(objects.size(), threads, [&](size_t k) {
        Object local = *objects[k];
        local.transform = Transform{};
        meshes[k] = tessellate(local, options);
        // A shape's tessellation has uvs and no tangents: made from them, as the ray tracers'
        // shapes give theirs (meshes bring their own, or the scene made them).
        if (!std::holds_alternative<Mesh>(local.shape) && meshes[k].tangents.empty())
            meshes[k].tangents = mesh_tangents(meshes[k]);
    });
    return meshes;
}

void size_list(TriangleList& list, size_t vertices, size_t triangles, bool second_set,
               bool colored) {
    list.positions.resize(vertices);
    list.normals.resize(vertices);
    list.uvs.resize(vertices);
    list.uvs1.resize(second_set ? vertices : 0);
    list.colors.resize(colored ? vertices : 0);
    list.tangents.resize(vertices);
    list.indices.resize(3 * triangles);
    list.material.resize(triangles);
}

void place_mesh(const Mesh& m, const Transform& transform, int material, TriangleList& list,
                size_t first_vertex, size_t first_triangle) {
    const mat3 nm = normal_matrix(transform.matrix);
    for (size_t v = 0; v < m.positions.size(); ++v)
        place_vertex(m, v, transform, nm, list, first_vertex + v);
    for (size_t t = 0; t < m.triangle_count(); ++t) {
        for (int c = 0; c < 3; ++c) {
            list.indices[3 * (first_triangle + t) + c] =
                static_cast<uint32_t>(first_vertex + m.indices[3 * t + c]);
        }
        list.material[first_triangle + t] =
            static_cast<uint32_t>(material >= 0 ? material : m.face_material[t]);
    }
}

TriangleList build_triangle_list(const std::vector<const Object*>& objects,
                                 const TessellationOptions& options, int threads) {
    const std::vector<Mesh> meshes = local_meshes(objects, options, threads);
    TriangleList list;
    size_t vertices = 0, triangles = 0;
    bool second_set = false, colored = false;
    for (const Mesh& m : meshes) {
        vertices += m.positions.size();
        triangles += m.triangle_count();
        second_set = second_set || !m.uvs1.empty();
        colored = colored || !m.colors.empty();
    }
    size_list(list, vertices, triangles, second_set, colored);
    list.objects.resize(objects.size());
    list.convex.resize(objects.size());
    list.centroid.resize(objects.size());
    for (size_t k = 0; k < objects.size(); ++k) list.convex[k] = tessellates_convex(*objects[k]);
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
        place_mesh(m, objects[k]->transform, -1, list, first_vertex[k], first_triangle[k]);
        glm::dvec3 sum(0.0);
        for (size_t v = 3 * first_triangle[k]; v < 3 * (first_triangle[k] + m.triangle_count());
             ++v)
            sum += glm::dvec3(list.positions[list.indices[v]]);
        if (m.triangle_count() > 0)
            list.centroid[k] = vec3(sum / (3.0 * static_cast<double>(m.triangle_count())));
    });
    return list;
}

namespace {

/// One id per distinct position, in the order of first appearance (-0 and +0 alike; a NaN
/// coordinate matches nothing): open addressing over a table of twice the vertices.
std::vector<uint32_t> weld_positions(const std::vector<vec3>& positions) {
    constexpr uint32_t kEmpty = ~0u;
    size_t capacity = 16;
    while (capacity < 2 * positions.size()) capacity *= 2;
    const size_t mask = capacity - 1;
    std::vector<uint32_t> first(capacity, kEmpty);  // the first vertex at a position
    std::vector<uint32_t> weld(positions.size());
    uint32_t ids = 0;
    for (size_t v = 0; v < positions.size(); ++v) {
        const vec3 p = positions[v] + vec3(0.0f);  // -0 and +0 are one position
        uint32_t b[3];
        std::memcpy(b, &p, sizeof(b));
        size_t slot = ((b[0] * 73856093u) ^ (b[1] * 19349663u) ^ (b[2] * 83492791u)) & mask;
        for (;; slot = (slot + 1) & mask) {
            if (first[slot] == kEmpty) {
                first[slot] = static_cast<uint32_t>(v);
                weld[v] = ids++;
                break;
            }
            const vec3 q = positions[first[slot]] + vec3(0.0f);
            if (q == p) {
                weld[v] = weld[first[slot]];
                break;
            }
        }
    }
    return weld;
}

}  // namespace

void build_adjacency(TriangleList& list) {
    const std::vector<uint32_t> weld = weld_positions(list.positions);
    // Every directed edge, grouped by its undirected key (lower id, higher id), each group in
    // the order of its slots (3 t + e): a manifold edge is a group of two, wound opposite
    // ways. A counting sort by the lower id, then each vertex's few edges by the higher.
    struct Edge {
        uint32_t high;
        uint32_t slot;  // 3 t + e
        bool forward;   // from the lower welded id to the higher
    };
    const size_t count = list.triangle_count();
    const size_t ids = weld.empty() ? 0 : *std::max_element(weld.begin(), weld.end()) + 1;
    std::vector<uint32_t> start(ids + 1, 0);
    auto each_edge = [&](auto&& visit) {
        for (size_t t = 0; t < count; ++t) {
            const uint32_t w[3] = {weld[list.indices[3 * t]], weld[list.indices[3 * t + 1]],
                                   weld[list.indices[3 * t + 2]]};
            // A triangle with two vertices alike (a sphere's pole row, a cone's apex) has no
            // area and joins nothing: its neighbours join each other across it.
            if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
            for (int e = 0; e < 3; ++e) {
                const uint32_t a = w[e], b = w[(e + 1) % 3];
                visit(std::min(a, b),
                      Edge{std::max(a, b), static_cast<uint32_t>(3 * t + e), a < b});
            }
        }
    };
    each_edge([&](uint32_t low, const Edge&) { ++start[low + 1]; });
    for (size_t k = 0; k < ids; ++k) start[k + 1] += start[k];
    std::vector<Edge> edges(start[ids]);
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    each_edge([&](uint32_t low, const Edge& e) { edges[fill[low]++] = e; });
    list.neighbour.assign(3 * count, TriangleList::kOpen);
    for (size_t low = 0; low < ids; ++low) {
        Edge* first = edges.data() + start[low];
        Edge* last = edges.data() + start[low + 1];
        // By the higher id, stable: the slots stay in order within a key (insertion sort: a
        // vertex has a few edges).
        for (Edge* i = first + 1; i < last; ++i) {
            const Edge e = *i;
            Edge* j = i;
            for (; j > first && (j - 1)->high > e.high; --j) *j = *(j - 1);
            *j = e;
        }
        for (Edge* i = first; i < last;) {
            Edge* j = i;
            while (j < last && j->high == i->high) ++j;
            if (j - i == 2 && i[0].forward != i[1].forward) {
                list.neighbour[i[0].slot] = i[1].slot / 3;
                list.neighbour[i[1].slot] = i[0].slot / 3;
            }
            i = j;
        }
    }
}

std::vector<char> closed_objects(const TriangleList& list) {
    std::vector<char> closed(list.objects.size(), 1);
    for (size_t o = 0; o < list.objects.size(); ++o) {
        for (uint32_t t = list.objects[o].first; t < list.objects[o].end && closed[o]; ++t) {
            const vec3 a = list.positions[list.indices[3 * t]],
                       b = list.positions[list.indices[3 * t + 1]],
                       c = list.positions[list.indices[3 * t + 2]];
            if (a == b || b == c || c == a) continue;  // (build_adjacency's weld: -0 == +0)
            for (int e = 0; e < 3; ++e) {
                if (list.neighbour[3 * t + e] == TriangleList::kOpen) closed[o] = 0;
            }
        }
    }
    return closed;
}

}  // namespace svetlo
