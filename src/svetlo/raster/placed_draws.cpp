#include "svetlo/raster/placed_draws.h"

#include <algorithm>
#include <functional>
#include <unordered_map>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

namespace {

/// A part's first faces (PlacedDraws::Part): of each vertex, and of each corner's vertex with
/// its triangle's material.
template <class Part>
void first_faces(Part& part) {
    const Mesh& m = part.mesh;
    part.first_any.assign(m.positions.size(), ~0u);
    part.first_same.assign(m.indices.size(), 0);
    const bool one_material = std::adjacent_find(m.face_material.begin(), m.face_material.end(),
                                                 std::not_equal_to<>()) == m.face_material.end();
    if (one_material) {  // (the common case: a vertex's first face is its first with it)
        for (size_t t = m.triangle_count(); t-- > 0;)
            for (int c = 0; c < 3; ++c)
                part.first_any[m.indices[3 * t + c]] = static_cast<uint32_t>(t);
        for (size_t k = 0; k < m.indices.size(); ++k)
            part.first_same[k] = part.first_any[m.indices[k]];
        return;
    }
    std::unordered_map<uint64_t, uint32_t> first;  // (vertex, material) -> face
    for (size_t t = 0; t < m.triangle_count(); ++t) {
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = m.indices[3 * t + c];
            if (part.first_any[v] == ~0u) part.first_any[v] = static_cast<uint32_t>(t);
            const uint64_t key = (uint64_t{v} << 32) | static_cast<uint32_t>(m.face_material[t]);
            part.first_same[3 * t + c] =
                first.try_emplace(key, static_cast<uint32_t>(t)).first->second;
        }
    }
}

}  // namespace

PlacedDraws::PlacedDraws(const Scene& scene, const TessellationOptions& options, uint32_t first_id,
                         bool adjacency, int threads)
    : adjacency_(adjacency) {
    // Each prototype an instance places, tessellated once.
    std::vector<int> index(scene.prototypes.size(), -1);
    for (const Instance& instance : scene.instances) {
        int& k = index[instance.prototype];
        if (k < 0) {
            const auto& objects = scene.prototypes[instance.prototype].objects;
            std::vector<const Object*> pointers;
            for (const Object& o : objects) pointers.push_back(&o);
            std::vector<Mesh> meshes = local_meshes(pointers, options, threads);
            Prototype p;
            p.first.push_back(0);
            p.first_vertex.push_back(0);
            for (size_t m = 0; m < meshes.size(); ++m) {
                Part part{std::move(meshes[m]), objects[m].transform, {}, {}, {}, {}};
                for (vec3 v : part.mesh.positions) part.bounds.extend(v);
                first_faces(part);
                if (adjacency) {  // the part's own, welded in its own space
                    TriangleList local;
                    size_list(local, part.mesh.positions.size(), part.mesh.triangle_count(), false,
                              false);
                    place_mesh(part.mesh, Transform{}, 0, local, 0, 0);
                    build_adjacency(local);
                    part.neighbour = std::move(local.neighbour);
                }
                p.first_vertex.push_back(p.first_vertex.back() + part.mesh.positions.size());
                second_set_ = second_set_ || !part.mesh.uvs1.empty();
                colored_ = colored_ || !part.mesh.colors.empty();
                p.first.push_back(p.first.back() + part.mesh.triangle_count());
                p.parts.push_back(std::move(part));
            }
            k = static_cast<int>(prototypes_.size());
            prototypes_.push_back(std::move(p));
        }
        placements_.push_back({static_cast<uint32_t>(k), instance.transform, instance.material});
    }
    for (const Placement& p : placements_) {
        Bounds3 box;
        for (const Part& part : prototypes_[p.prototype].parts)
            if (!part.bounds.empty())
                box.extend(transformed_bounds(part.bounds, part_transform(p, part).matrix));
        boxes_.push_back(box);
    }
    first_.push_back(first_id);
    first_vertex_.push_back(0);
    for (size_t p = 0; p < placements_.size(); ++p) {
        first_.push_back(first_.back() + prototypes_[placements_[p].prototype].first.back());
        first_vertex_.push_back(first_vertex_.back() + vertices(p));
    }
    // kNoPrimitive (~0) marks an empty sample in the item buffer.
    if (end_id() >= RenderTargets::kNoPrimitive) {
        throw Error(scene.path.string(), "objects",
                    "the scene and its instances stand for " + std::to_string(end_id()) +
                        " triangles; the rasterizer numbers at most " +
                        std::to_string(RenderTargets::kNoPrimitive - 1));
    }
}

Transform PlacedDraws::part_transform(const Placement& p, const Part& part) const {
    Transform t;
    t.matrix = p.transform.matrix * part.transform.matrix;
    t.is_identity = p.transform.is_identity && part.transform.is_identity;
    return t;
}

void PlacedDraws::write(size_t p, TriangleList& list, size_t v, size_t t) const {
    const Placement& placement = placements_[p];
    for (const Part& part : prototypes_[placement.prototype].parts) {
        place_mesh(part.mesh, part_transform(placement, part), placement.material, list, v, t);
        v += part.mesh.positions.size();
        t += part.mesh.triangle_count();
    }
}

Bounds3 PlacedDraws::bounds() const {
    Bounds3 b;
    for (const Bounds3& box : boxes_)
        if (!box.empty()) b.extend(box);
    return b;
}

float PlacedDraws::nearest_depth(vec3 eye, vec3 forward, int threads) const {
    return parallel_min(
        placements_.size(), threads,
        [&](size_t begin, size_t end) {
            float least = kInfinity;
            for (size_t p = begin; p < end; ++p) {
                for (const Part& part : prototypes_[placements_[p].prototype].parts) {
                    if (part.bounds.empty()) continue;
                    const Transform t = part_transform(placements_[p], part);
                    const Bounds3 box = transformed_bounds(part.bounds, t.matrix);
                    float lo = kInfinity, hi = -kInfinity;  // the corners' depths
                    for (int k = 0; k < 8; ++k) {
                        const vec3 corner((k & 1) ? box.max.x : box.min.x,
                                          (k & 2) ? box.max.y : box.min.y,
                                          (k & 4) ? box.max.z : box.min.z);
                        const float w = glm::dot(corner - eye, forward);
                        lo = std::min(lo, w);
                        hi = std::max(hi, w);
                    }
                    if (hi <= 0.0f) continue;  // wholly behind
                    if (lo > 0.0f) {           // wholly in front: no point nearer
                        least = std::min(least, lo);
                        continue;
                    }
                    // Across the eye's plane: each triangle, as the frame's own list.
                    const Mesh& m = part.mesh;
                    for (size_t tri = 0; tri < m.triangle_count(); ++tri) {
                        vec3 c[3];
                        for (int j = 0; j < 3; ++j)
                            c[j] = vec3(t.matrix * vec4(m.positions[m.indices[3 * tri + j]], 1.0f));
                        least = std::min(least, nearest_plane(c[0], c[1], c[2], eye, forward));
                    }
                }
            }
            return least;
        },
        64);
}

namespace {

/// Whether box `b` lies wholly outside one side of the clip volume of `view_projection`
/// (|x| <= w, |y| <= w, w > 0): no sample of the film sees it.
bool outside_view(const mat4& view_projection, const Bounds3& b) {
    int left = 0, right = 0, below = 0, above = 0, behind = 0;
    for (int k = 0; k < 8; ++k) {
        const vec4 c =
            view_projection * vec4((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                                   (k & 4) ? b.max.z : b.min.z, 1.0f);
        left += c.x < -c.w;
        right += c.x > c.w;
        below += c.y < -c.w;
        above += c.y > c.w;
        behind += c.w <= 0.0f;
    }
    return left == 8 || right == 8 || below == 8 || above == 8 || behind == 8;
}

}  // namespace

void PlacedDraws::for_each_batch(const mat4* view_projection, int threads, TriangleList& scratch,
                                 const BatchVisit& visit) const {
    // The placements drawn: those a view may see, or all.
    std::vector<char> seen(placements_.size(), 1);
    if (view_projection) {
        parallel_indices(placements_.size(), threads, [&](size_t p) {
            seen[p] = !boxes_[p].empty() && !outside_view(*view_projection, boxes_[p]);
        });
    }
    std::vector<uint32_t> items;  // the batch's triangles' ids
    std::vector<size_t> batch;    // its placements
    std::vector<uint64_t> first_vertex, first_triangle, first_object;
    for (size_t p = 0; p < placements_.size();) {
        // A batch: placements while their triangles stay within kBatchTriangles.
        batch.clear();
        first_vertex.assign(1, 0);
        first_triangle.assign(1, 0);
        first_object.assign(1, 0);
        for (; p < placements_.size(); ++p) {
            if (!seen[p]) continue;
            const uint64_t count = first_[p + 1] - first_[p];
            if (!batch.empty() && first_triangle.back() + count > kBatchTriangles) break;
            batch.push_back(p);
            first_vertex.push_back(first_vertex.back() + vertices(p));
            first_triangle.push_back(first_triangle.back() + count);
            first_object.push_back(first_object.back() +
                                   prototypes_[placements_[p].prototype].parts.size());
        }
        if (batch.empty()) break;
        size_list(scratch, first_vertex.back(), first_triangle.back(), second_set_, colored_);
        scratch.objects.resize(first_object.back());
        scratch.neighbour.resize(adjacency_ ? 3 * first_triangle.back() : 0);
        items.resize(first_triangle.back());
        parallel_indices(batch.size(), threads, [&](size_t k) {
            write(batch[k], scratch, first_vertex[k], first_triangle[k]);
            const Prototype& proto = prototypes_[placements_[batch[k]].prototype];
            for (size_t part = 0; part < proto.parts.size(); ++part) {
                const auto t0 = static_cast<uint32_t>(first_triangle[k] + proto.first[part]);
                const auto t1 = static_cast<uint32_t>(first_triangle[k] + proto.first[part + 1]);
                scratch.objects[first_object[k] + part] = {t0, t1};
                if (!adjacency_) continue;
                const std::vector<uint32_t>& nb = proto.parts[part].neighbour;
                for (size_t e = 0; e < nb.size(); ++e)
                    scratch.neighbour[3 * size_t{t0} + e] =
                        nb[e] == TriangleList::kOpen ? TriangleList::kOpen : t0 + nb[e];
            }
            for (uint64_t t = first_triangle[k]; t < first_triangle[k + 1]; ++t)
                items[t] = static_cast<uint32_t>(first_[batch[k]] + (t - first_triangle[k]));
        });
        visit(scratch, items, batch);
    }
}

void PlacedDraws::draw(const CameraMatrices& camera, const PipelineState& state,
                       RenderTargets& targets, const SamplePattern& pattern, int threads,
                       PassMemory* memory, TriangleList& scratch) const {
    const mat4 view_projection = camera.view_projection();
    for_each_batch(&view_projection, threads, scratch,
                   [&](const TriangleList& batch, const std::vector<uint32_t>& items,
                       const std::vector<size_t>&) {
                       PipelineState batch_state = state;
                       batch_state.items = items.data();
                       draw_samples(batch, camera, batch_state, targets, threads, pattern, memory);
                   });
}

PlacedDraws::Located PlacedDraws::locate(uint32_t id) const {
    const auto p =
        static_cast<size_t>(std::upper_bound(first_.begin(), first_.end(), id) - first_.begin()) -
        1;
    const Prototype& proto = prototypes_[placements_[p].prototype];
    const uint64_t local = id - first_[p];
    const auto k =
        static_cast<size_t>(std::upper_bound(proto.first.begin(), proto.first.end(), local) -
                            proto.first.begin()) -
        1;
    return {p, k, static_cast<size_t>(local - proto.first[k])};
}

void PlacedDraws::corners(uint32_t id, Corner out[3]) const {
    const auto [p, k, t] = locate(id);
    const Placement& placement = placements_[p];
    const Prototype& proto = prototypes_[placement.prototype];
    const Part& part = proto.parts[k];
    const uint64_t part_first_id = first_[p] + proto.first[k];
    const auto material = static_cast<uint32_t>(
        placement.material >= 0 ? placement.material : part.mesh.face_material[t]);
    for (int c = 0; c < 3; ++c) {
        const uint32_t v = part.mesh.indices[3 * t + c];
        // Under the instance's material every face has one material: the vertex's first.
        const uint32_t first =
            placement.material >= 0 ? part.first_any[v] : part.first_same[3 * t + c];
        out[c] = {first_vertex_[p] + proto.first_vertex[k] + v, material,
                  static_cast<uint32_t>(part_first_id + first)};
    }
}

void PlacedDraws::write_vertices(const uint64_t* vertices, size_t count, uint64_t base,
                                 TriangleList& list, size_t first) const {
    size_t p = 0, k = 0;
    uint64_t part_first = 1, part_end = 0;  // the current part's vertices: none yet
    Transform t;
    mat3 nm(1.0f);
    for (size_t j = 0; j < count; ++j) {
        const uint64_t vertex = vertices[j] - base;
        if (vertex < part_first || vertex >= part_end) {  // another part: found, and placed
            p = static_cast<size_t>(
                    std::upper_bound(first_vertex_.begin(), first_vertex_.end(), vertex) -
                    first_vertex_.begin()) -
                1;
            const Prototype& proto = prototypes_[placements_[p].prototype];
            const uint64_t local = vertex - first_vertex_[p];
            k = static_cast<size_t>(
                    std::upper_bound(proto.first_vertex.begin(), proto.first_vertex.end(), local) -
                    proto.first_vertex.begin()) -
                1;
            part_first = first_vertex_[p] + proto.first_vertex[k];
            part_end = first_vertex_[p] + proto.first_vertex[k + 1];
            t = part_transform(placements_[p], proto.parts[k]);
            nm = normal_matrix(t.matrix);
        }
        const Part& part = prototypes_[placements_[p].prototype].parts[k];
        place_vertex(part.mesh, vertex - part_first, t, nm, list, first + j);
    }
}

void PlacedDraws::add_to(Geometry& g) const {
    std::vector<std::vector<uint32_t>> index(prototypes_.size());  // per part, in g.prototypes
    for (size_t k = 0; k < prototypes_.size(); ++k) {
        for (const Part& part : prototypes_[k].parts) {
            TriangleList list;
            size_list(list, part.mesh.positions.size(), part.mesh.triangle_count(),
                      !part.mesh.uvs1.empty(), !part.mesh.colors.empty());
            place_mesh(part.mesh, Transform{}, -1, list, 0, 0);
            index[k].push_back(static_cast<uint32_t>(g.prototypes.size()));
            g.prototypes.push_back(std::make_shared<Geometry>(triangle_geometry(list)));
        }
    }
    for (const Placement& p : placements_) {
        const auto& parts = prototypes_[p.prototype].parts;
        for (size_t k = 0; k < parts.size(); ++k) {
            if (parts[k].bounds.empty()) continue;
            g.placements.push_back(make_placement(
                index[p.prototype][k], part_transform(p, parts[k]), p.material, parts[k].bounds));
        }
    }
}

Bounds3 SceneTriangles::bounds() const {
    Bounds3 b = list.bounds();
    if (placed) b.extend(placed->bounds());
    return b;
}

void SceneTriangles::draw(const CameraMatrices& camera, const PipelineState& state,
                          RenderTargets& targets, const SamplePattern& pattern, int threads,
                          PassMemory* memory) const {
    draw_samples(list, camera, state, targets, threads, pattern, memory);
    if (placed) placed->draw(camera, state, targets, pattern, threads, memory, scratch);
}

namespace {

/// The triangles of `scene` that hold a sample of one of `passes`: their ids, in order.
std::vector<uint32_t> held_triangles(const SceneTriangles& scene, const CameraMatrices& camera,
                                     const PipelineState& state,
                                     const std::vector<SamplePattern>& passes, int threads,
                                     PassMemory* memory) {
    std::vector<uint32_t> ids;
    RenderTargets targets;
    for (const SamplePattern& sp : passes) {
        targets.clear(camera.width, camera.height, sp.count, false, true);
        scene.draw(camera, state, targets, sp, threads, memory);
        uint32_t last = RenderTargets::kNoPrimitive;
        for (uint32_t id : targets.primitive) {
            if (id != RenderTargets::kNoPrimitive && id != last) ids.push_back(id);
            last = id;
        }
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
}

/// The corners of the scene's triangles (PlacedDraws::Corner): the list's vertices first,
/// then the placements' after them. The list's first faces are found only when asked for
/// (`first_faces`); the list is split by material under Gouraud, so a vertex has one.
class SceneCorners {
public:
    SceneCorners(const SceneTriangles& scene, bool first_faces)
        : own_(scene.list), placed_(scene.placed), first_faces_(first_faces) {
        if (!first_faces) return;
        own_first_.assign(own_.positions.size(), ~0u);
        for (auto t = static_cast<uint32_t>(own_.triangle_count()); t-- > 0;)
            for (int c = 0; c < 3; ++c) own_first_[own_.indices[3 * size_t{t} + c]] = t;
    }

    void of(uint32_t id, PlacedDraws::Corner out[3]) const {
        if (id >= own_.triangle_count()) {
            placed_->corners(id, out);
            for (int c = 0; c < 3; ++c) out[c].vertex += own_.positions.size();
            return;
        }
        for (int c = 0; c < 3; ++c) {
            const uint32_t v = own_.indices[3 * size_t{id} + c];
            out[c] = {v, own_.material[id], first_faces_ ? own_first_[v] : id};
        }
    }

    /// Writes scene vertex `vertices[i]` into vertex i of `list` (sized), for i in [begin,
    /// end), ascending: the list's copied, the placements' placed.
    void write(const std::vector<uint64_t>& vertices, size_t begin, size_t end,
               TriangleList& list) const {
        const size_t own = own_.positions.size();
        size_t i = begin;
        for (; i < end && vertices[i] < own; ++i) {
            const uint64_t v = vertices[i];
            list.positions[i] = own_.positions[v];
            list.normals[i] = own_.normals[v];
            list.uvs[i] = own_.uvs[v];
            if (!list.uvs1.empty()) list.uvs1[i] = own_.uvs1.empty() ? own_.uvs[v] : own_.uvs1[v];
            if (!list.colors.empty())
                list.colors[i] = own_.colors.empty() ? vec4(1.0f) : own_.colors[v];
            list.tangents[i] = own_.tangents[v];
        }
        if (i < end) placed_->write_vertices(&vertices[i], end - i, own, list, i);
    }

private:
    const TriangleList& own_;
    const PlacedDraws* placed_;
    bool first_faces_;
    std::vector<uint32_t> own_first_;  // per vertex of the list, the first face that uses it
};

}  // namespace

VisibleTriangles visible_triangles(const SceneTriangles& scene, const CameraMatrices& camera,
                                   const PipelineState& state,
                                   const std::vector<SamplePattern>& passes, bool first_faces,
                                   int threads, PassMemory* memory) {
    std::vector<uint32_t> ids = held_triangles(scene, camera, state, passes, threads, memory);
    const SceneCorners corners(scene, first_faces);
    if (first_faces) {
        const size_t held = ids.size();
        for (size_t i = 0; i < held; ++i) {
            PlacedDraws::Corner c[3];
            corners.of(ids[i], c);
            for (const auto& corner : c) ids.push_back(corner.first_face);
        }
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    }

    // Every corner's key, sorted: one vertex per (vertex, material).
    struct Key {
        uint64_t vertex;
        uint32_t material;
        uint32_t corner;  // 3 i + c
    };
    std::vector<Key> keys(3 * ids.size());
    std::vector<uint32_t> material(ids.size());
    parallel_ranges(
        ids.size(), threads,
        [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                PlacedDraws::Corner c[3];
                corners.of(ids[i], c);
                for (uint32_t k = 0; k < 3; ++k)
                    keys[3 * i + k] = {c[k].vertex, c[k].material,
                                       static_cast<uint32_t>(3 * i + k)};
                material[i] = c[0].material;
            }
        },
        4096);
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        return a.vertex != b.vertex ? a.vertex < b.vertex : a.material < b.material;
    });
    std::vector<uint64_t> vertices;  // of the scene, one per vertex of the list, ascending
    std::vector<uint32_t> indices(keys.size());
    for (size_t k = 0; k < keys.size(); ++k) {
        if (k == 0 || keys[k].vertex != keys[k - 1].vertex ||
            keys[k].material != keys[k - 1].material)
            vertices.push_back(keys[k].vertex);
        indices[keys[k].corner] = static_cast<uint32_t>(vertices.size() - 1);
    }

    TriangleList out;
    const PlacedDraws* placed = scene.placed;
    size_list(out, vertices.size(), ids.size(),
              !scene.list.uvs1.empty() || (placed && placed->second_set()),
              !scene.list.colors.empty() || (placed && placed->colored()));
    out.indices = std::move(indices);
    parallel_ranges(
        vertices.size(), threads,
        [&](size_t begin, size_t end) { corners.write(vertices, begin, end, out); }, 4096);
    out.material = std::move(material);
    return {std::move(out), std::move(ids)};
}

}  // namespace svetlo::raster
