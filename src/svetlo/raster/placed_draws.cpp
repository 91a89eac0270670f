#include "svetlo/raster/placed_draws.h"

#include <algorithm>
#include <mutex>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/raster/pipeline.h"

namespace svetlo::raster {

PlacedDraws::PlacedDraws(const Scene& scene, const TessellationOptions& options, uint32_t first_id,
                         int threads) {
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
            for (size_t m = 0; m < meshes.size(); ++m) {
                Part part{std::move(meshes[m]), objects[m].transform, {}};
                for (vec3 v : part.mesh.positions) part.bounds.extend(v);
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
    for (const Placement& p : placements_)
        first_.push_back(first_.back() + prototypes_[p.prototype].first.back());
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

uint64_t PlacedDraws::vertices(size_t p) const {
    uint64_t n = 0;
    for (const Part& part : prototypes_[placements_[p].prototype].parts)
        n += part.mesh.positions.size();
    return n;
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
    std::mutex mutex;
    float nearest = kInfinity;
    parallel_ranges(
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
                        if (glm::dot(c[0] - eye, forward) <= 0.0f &&
                            glm::dot(c[1] - eye, forward) <= 0.0f &&
                            glm::dot(c[2] - eye, forward) <= 0.0f)
                            continue;
                        const vec3 n = triangle_normal(c[0], c[1], c[2]);
                        least = std::min(least, std::abs(glm::dot(n, eye - c[0])));
                    }
                }
            }
            std::lock_guard lock(mutex);
            nearest = std::min(nearest, least);
        },
        64);
    return nearest;
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

void PlacedDraws::draw(const CameraMatrices& camera, const PipelineState& state,
                       RenderTargets& targets, const SamplePattern& pattern, int threads,
                       PassMemory* memory, TriangleList& scratch) const {
    // The placements the camera may see.
    const mat4 view_projection = camera.view_projection();
    std::vector<char> seen(placements_.size());
    parallel_indices(placements_.size(), threads, [&](size_t p) {
        seen[p] = !boxes_[p].empty() && !outside_view(view_projection, boxes_[p]);
    });
    std::vector<uint32_t> items;  // the batch's triangles' ids
    std::vector<size_t> batch;    // its placements
    std::vector<uint64_t> first_vertex, first_triangle;
    for (size_t p = 0; p < placements_.size();) {
        // A batch: placements seen while their triangles stay within kBatchTriangles.
        batch.clear();
        first_vertex.assign(1, 0);
        first_triangle.assign(1, 0);
        for (; p < placements_.size(); ++p) {
            if (!seen[p]) continue;
            const uint64_t count = first_[p + 1] - first_[p];
            if (!batch.empty() && first_triangle.back() + count > kBatchTriangles) break;
            batch.push_back(p);
            first_vertex.push_back(first_vertex.back() + vertices(p));
            first_triangle.push_back(first_triangle.back() + count);
        }
        if (batch.empty()) break;
        size_list(scratch, first_vertex.back(), first_triangle.back(), second_set_, colored_);
        items.resize(first_triangle.back());
        parallel_indices(batch.size(), threads, [&](size_t k) {
            write(batch[k], scratch, first_vertex[k], first_triangle[k]);
            for (uint64_t t = first_triangle[k]; t < first_triangle[k + 1]; ++t)
                items[t] = static_cast<uint32_t>(first_[batch[k]] + (t - first_triangle[k]));
        });
        PipelineState batch_state = state;
        batch_state.items = items.data();
        draw_samples(scratch, camera, batch_state, targets, threads, pattern, memory);
    }
}

void PlacedDraws::write_triangles(const std::vector<uint32_t>& ids, size_t begin, size_t end,
                                  TriangleList& list) const {
    for (size_t i = begin; i < end; ++i) {
        const uint32_t id = ids[i];
        const size_t p = static_cast<size_t>(std::upper_bound(first_.begin(), first_.end(), id) -
                                             first_.begin()) -
                         1;
        const Placement& placement = placements_[p];
        const Prototype& proto = prototypes_[placement.prototype];
        const uint64_t local = id - first_[p];
        const size_t k =
            static_cast<size_t>(std::upper_bound(proto.first.begin(), proto.first.end(), local) -
                                proto.first.begin()) -
            1;
        const Part& part = proto.parts[k];
        const size_t tri = local - proto.first[k];
        const Transform t = part_transform(placement, part);
        const mat3 nm = normal_matrix(t.matrix);
        for (int c = 0; c < 3; ++c) {
            place_vertex(part.mesh, part.mesh.indices[3 * tri + c], t, nm, list, 3 * i + c);
            list.indices[3 * i + c] = static_cast<uint32_t>(3 * i + c);
        }
        list.material[i] = static_cast<uint32_t>(
            placement.material >= 0 ? placement.material : part.mesh.face_material[tri]);
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
    if (placed) {
        TriangleList scratch;
        placed->draw(camera, state, targets, pattern, threads, memory, scratch);
    }
}

TriangleList visible_triangles(const SceneTriangles& scene, const CameraMatrices& camera,
                               const PipelineState& state, const std::vector<SamplePattern>& passes,
                               int threads, PassMemory* memory) {
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

    const TriangleList& own = scene.list;
    const PlacedDraws* placed = scene.placed;
    TriangleList out;
    const bool second_set = !own.uvs1.empty() || (placed && placed->second_set());
    const bool colored = !own.colors.empty() || (placed && placed->colored());
    size_list(out, 3 * ids.size(), ids.size(), second_set, colored);
    const size_t own_count = static_cast<size_t>(
        std::lower_bound(ids.begin(), ids.end(), static_cast<uint32_t>(own.triangle_count())) -
        ids.begin());
    parallel_ranges(
        ids.size(), threads,
        [&](size_t begin, size_t end) {
            // The list's own triangles: their vertices copied.
            for (size_t i = begin; i < std::min(end, own_count); ++i) {
                const uint32_t t = ids[i];
                for (int c = 0; c < 3; ++c) {
                    const uint32_t from = own.indices[3 * t + c];
                    const size_t to = 3 * i + c;
                    out.positions[to] = own.positions[from];
                    out.normals[to] = own.normals[from];
                    out.uvs[to] = own.uvs[from];
                    if (second_set)
                        out.uvs1[to] = own.uvs1.empty() ? own.uvs[from] : own.uvs1[from];
                    if (colored)
                        out.colors[to] = own.colors.empty() ? vec4(1.0f) : own.colors[from];
                    out.tangents[to] = own.tangents[from];
                    out.indices[to] = static_cast<uint32_t>(to);
                }
                out.material[i] = own.material[t];
            }
            if (placed && end > own_count)
                placed->write_triangles(ids, std::max(begin, own_count), end, out);
        },
        4096);
    return out;
}

}  // namespace svetlo::raster
