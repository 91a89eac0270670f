// render.shadows "planar": projected shadows (Blinn, "Me and My (Fake) Shadow", IEEE CG&A
// 1988). The occluders are flattened onto each planar receiver by the projection matrix of
// the pair (light, plane), and drawn from the camera through the stencil buffer:
//
//   1. receivers: per object, its triangles grouped by plane; a group of at least 1% of the
//      object's area is a receiver (a quad, a plane, a box's faces, a flat mesh, a cylinder's
//      caps). Curved surfaces have no such group: they receive no planar shadow, which is the
//      technique's known limit.
//   2. per sample pass, a pass from the camera with an item buffer, and per caster the
//      stencil set to the receiver's number (1 to 127) on the samples it covers;
//   3. per receiver, every other triangle is clipped to the slab between the plane and the
//      caster, which removes the false shadows of occluders behind the light and on the far
//      side of the receiver, projected onto the plane, and drawn with the stencil test
//      "equal to the receiver's number" (so the shadow stays on the receiver's own pixels,
//      with no depth test and no z-fighting), setting the top bit (so it never darkens twice).
#include <algorithm>
#include <array>

#include "svetlo/core/error.h"
#include "svetlo/raster/placed_draws.h"
#include "svetlo/raster/shadow_techniques.h"

namespace svetlo::raster {

namespace {

constexpr int kReceiversPerRound = 127;  // stencil values 1..127; bit 7 marks the shadow

struct Receiver {
    vec3 normal{0.0f};    // unit
    float offset = 0.0f;  // the plane: dot(normal, x) = offset
    float area = 0.0f;
    std::vector<uint32_t> triangles;
};

/// The planar receivers of every object (see the file's comment).
std::vector<Receiver> find_receivers(const TriangleList& list, float diameter) {
    constexpr size_t kMaxPlanesPerObject = 256;
    std::vector<Receiver> receivers;
    for (const PrimitiveRange& range : list.objects) {
        std::vector<Receiver> planes;
        float total = 0.0f;
        for (uint32_t t = range.first; t < range.end; ++t) {
            vec3 a = list.positions[list.indices[3 * t]],
                 b = list.positions[list.indices[3 * t + 1]],
                 c = list.positions[list.indices[3 * t + 2]];
            vec3 cr = glm::cross(b - a, c - a);
            float area = 0.5f * glm::length(cr);
            if (!(area > 0.0f)) continue;
            total += area;
            vec3 n = cr / (2.0f * area);
            float d = glm::dot(n, a);
            Receiver* match = nullptr;
            for (Receiver& r : planes) {
                if (glm::dot(r.normal, n) > 1.0f - 1e-4f &&
                    std::abs(r.offset - d) <= 1e-5f * diameter) {
                    match = &r;
                    break;
                }
            }
            if (!match) {
                if (planes.size() == kMaxPlanesPerObject) continue;  // a curved surface
                planes.push_back({n, d, 0.0f, {}});
                match = &planes.back();
            }
            match->area += area;
            match->triangles.push_back(t);
        }
        for (Receiver& r : planes) {
            if (r.area >= 0.01f * total &&
                (r.triangles.size() >= 2 || range.end - range.first == 1))
                receivers.push_back(std::move(r));
        }
    }
    return receivers;
}

/// The projection onto the plane dot(n, x) = d from the homogeneous light position l (w = 1
/// for a point, 0 for a direction of travel's opposite): M = (P . l) I - l P^T, with the plane
/// P = (n, -d) (Blinn 1988). A point x maps to M x, the point where the line from the light
/// through x meets the plane.
mat4 planar_projection(vec3 n, float d, vec4 l) {
    const vec4 plane(n, -d);
    const float dot = glm::dot(plane, l);
    mat4 m(0.0f);
    for (int col = 0; col < 4; ++col) {
        for (int row = 0; row < 4; ++row)
            m[col][row] = (row == col ? dot : 0.0f) - l[row] * plane[col];
    }
    return m;
}

/// Clips polygon `in` to dist(x) >= 0 (Sutherland-Hodgman), dist affine.
template <class Dist>
int clip(const std::array<vec3, 8>& in, int count, std::array<vec3, 8>& out, Dist&& dist) {
    int n = 0;
    for (int k = 0; k < count; ++k) {
        vec3 a = in[static_cast<size_t>(k)], b = in[static_cast<size_t>((k + 1) % count)];
        float da = dist(a), db = dist(b);
        if (da >= 0.0f) out[static_cast<size_t>(n++)] = a;
        if ((da >= 0.0f) != (db >= 0.0f))
            out[static_cast<size_t>(n++)] = a + (da / (da - db)) * (b - a);
    }
    return n;
}

class PlanarShadows final : public StencilMasks {
public:
    PlanarShadows(const Scene& scene, const TriangleList& list, const FrameState& f,
                  const std::vector<SamplePattern>& passes, int threads, PassMemory* memory)
        : placed_(f.placed.get()) {
        // The scene's list, and its instances drawn in place (placed_draws.h).
        const SceneTriangles scene_triangles{list, placed_};
        const float diameter = scene_diameter(scene_triangles.bounds());
        casters_ =
            shadow_casters(scene, f.lights->set, scene.render.area_shadow_points, 1e-4f * diameter);
        // (The depth, stencil and item targets and each sample's receiver: 13 bytes.)
        reserve(scene, f.cam.width, f.cam.height, passes, 13, "planar shadows' masks");
        receivers_ = find_receivers(list, diameter);
        receiver_of_.assign(list.triangle_count(), 0);
        for (size_t r = 0; r < receivers_.size(); ++r) {
            for (uint32_t t : receivers_[r].triangles)
                receiver_of_[t] = static_cast<uint32_t>(r + 1);
        }
        if (placed_) place_receivers(diameter);
        // Alpha's holes (alpha_test.h): the receivers seen through them, and no shadow from
        // them (the projected triangles keep their casters' texture coordinates).
        alpha_test_ = std::make_unique<AlphaTest>(f.materials, scene.textures);
        const AlphaTest* alpha = alpha_test_->any() ? alpha_test_.get() : nullptr;
        PipelineState item_state;
        item_state.cull = f.cull;
        item_state.alpha = alpha;
        for (const SamplePattern& sp : passes) {
            RenderTargets targets;
            targets.clear(width_, height_, sp.count, true, true);
            scene_triangles.draw(f.cam, item_state, targets, sp, threads, memory);
            std::vector<uint32_t> receiver(targets.primitive.size(), 0);
            for (size_t i = 0; i < receiver.size(); ++i) {
                uint32_t t = targets.primitive[i];
                receiver[i] = t == RenderTargets::kNoPrimitive ? 0 : receiver_number(t);
            }
            for (size_t k = 0; k < casters_.size(); ++k) {
                std::vector<uint8_t> lit(receiver.size(), 1);
                for (size_t first = 0; first < receivers_.size(); first += kReceiversPerRound) {
                    const size_t last = std::min(receivers_.size(), first + kReceiversPerRound);
                    // The stencil holds each sample's receiver number within this round.
                    for (size_t i = 0; i < receiver.size(); ++i) {
                        uint32_t r = receiver[i];
                        targets.stencil[i] =
                            r > first && r <= last ? static_cast<uint8_t>(r - first) : uint8_t{0};
                    }
                    for (size_t r = first; r < last; ++r) {
                        PipelineState state;
                        state.depth_test = false;
                        state.depth_write = false;
                        state.write_items = false;
                        state.stencil.enabled = true;
                        state.stencil.ref = static_cast<uint8_t>(0x80 | (r - first + 1));
                        state.stencil.read_mask = 0x7f;
                        state.stencil.write_mask = 0x80;
                        state.stencil.front = {StencilFunc::Equal, StencilOp::Keep, StencilOp::Keep,
                                               StencilOp::Replace};
                        state.stencil.back = state.stencil.front;
                        state.alpha = alpha;
                        const bool clip = scene.render.shadow_teaching.planar_clip;
                        auto draw = [&](const TriangleList& occluders, auto&& own) {
                            TriangleList shadow =
                                projected(occluders, r, casters_[k], diameter, clip, own);
                            if (!shadow.indices.empty())
                                draw_samples(shadow, f.cam, state, targets, threads, sp, memory);
                            // The next batch's shadow numbered on: a blend's coins of its own.
                            state.first_item += static_cast<uint32_t>(shadow.triangle_count());
                        };
                        draw(list, [&](size_t t) { return receiver_of_[t] == r + 1; });
                        if (!placed_) continue;
                        placed_->for_each_batch(
                            nullptr, threads, scene_triangles.scratch,
                            [&](const TriangleList& batch, const std::vector<uint32_t>& items,
                                const std::vector<size_t>&) {
                                // Only its own placement's triangles may be the receiver's.
                                const std::pair<uint64_t, uint64_t> ids = receiver_ids(r);
                                draw(batch, [&](size_t t) {
                                    return items[t] >= ids.first && items[t] < ids.second &&
                                           receiver_number(items[t]) == r + 1;
                                });
                            });
                    }
                    for (size_t i = 0; i < lit.size(); ++i) {
                        if (targets.stencil[i] & 0x80) lit[i] = 0;
                    }
                }
                lit_[k].push_back(std::move(lit));
            }
        }
    }

private:
    /// Every triangle of `list` but the receiver's (`own`), clipped to the slab between the
    /// receiver's plane and the caster, flattened onto the plane from the caster.
    template <class Own>
    TriangleList projected(const TriangleList& list, size_t receiver, const ShadowCaster& c,
                           float diameter, bool clip_to_slab, Own&& own) const {
        const Receiver& r = receivers_[receiver];
        TriangleList out;
        const bool directional = c.kind == ShadowCaster::Kind::Directional;
        // The plane turned toward the caster; none when the caster lies in it or behind
        // nothing (a direction parallel to it).
        vec3 n = r.normal;
        float d = r.offset;
        float light_height = directional ? -glm::dot(n, c.direction) : glm::dot(n, c.position) - d;
        if (light_height < 0.0f) {
            n = -n;
            d = -d;
            light_height = -light_height;
        }
        if (!(light_height > 1e-6f * (directional ? 1.0f : diameter))) return out;
        const vec4 light = directional ? vec4(-c.direction, 0.0f) : vec4(c.position, 1.0f);
        const mat4 project = planar_projection(n, d, light);
        const float epsilon = 1e-5f * diameter;
        for (size_t t = 0; t < list.triangle_count(); ++t) {
            if (own(t)) continue;  // the receiver's own
            std::array<vec3, 8> a{}, b{};
            for (int k = 0; k < 3; ++k)
                a[static_cast<size_t>(k)] =
                    list.positions[list.indices[3 * t + static_cast<size_t>(k)]];
            // Above the plane (the far side casts nothing), and below the light (what lies
            // beyond it would project to the wrong side).
            int count = 3;
            if (clip_to_slab) {
                count = clip(a, 3, b, [&](vec3 x) { return glm::dot(n, x) - d - epsilon; });
                if (!directional && count >= 3)
                    count = clip(b, count, a, [&](vec3 x) {
                        return light_height - (glm::dot(n, x) - d) - epsilon;
                    });
                else
                    a = b;
            } else {
                // Without the fix (render.planar_shadows.clip false, for the docs' picture):
                // the whole triangle is projected, and what lies beyond the light lands on
                // the wrong side; only a vertex level with the light (w = 0) is left out.
                bool level = false;
                for (int k = 0; k < 3; ++k)
                    level |=
                        std::abs((project * vec4(a[static_cast<size_t>(k)], 1.0f)).w) < epsilon;
                if (level) continue;
            }
            if (count < 3) continue;
            auto first = static_cast<uint32_t>(out.positions.size());
            const uint32_t* v = &list.indices[3 * t];
            for (int k = 0; k < count; ++k) {
                const vec3 x = a[static_cast<size_t>(k)];
                vec4 h = project * vec4(x, 1.0f);
                out.positions.push_back(vec3(h) / h.w);
                // The caster's texture coordinates at x (a point of its triangle, clipped or
                // not), for the alpha test: interpolated over the shadow, they are exact for a
                // direction and close for a point (whose projection is not affine).
                const vec3 p0 = list.positions[v[0]], p1 = list.positions[v[1]],
                           p2 = list.positions[v[2]];
                const vec3 n2 = glm::cross(p1 - p0, p2 - p0);
                const float inv = 1.0f / std::max(glm::dot(n2, n2), 1e-30f);
                const float b1 = glm::dot(glm::cross(x - p0, p2 - p0), n2) * inv;
                const float b2 = glm::dot(glm::cross(p1 - p0, x - p0), n2) * inv;
                const Varyings at = list.varyings(t, vec2(b1, b2));
                out.uvs.push_back(at.uv[0]);
                if (!list.uvs1.empty()) out.uvs1.push_back(at.uv[1]);
                if (!list.colors.empty()) out.colors.push_back(at.color);
            }
            for (int k = 1; k + 1 < count; ++k) {
                out.indices.insert(out.indices.end(), {first, first + static_cast<uint32_t>(k),
                                                       first + static_cast<uint32_t>(k) + 1});
                out.material.push_back(list.material[t]);
            }
        }
        out.normals.assign(out.positions.size(), vec3(0.0f));
        return out;
    }

    /// The placements' receivers, after the list's: each prototype's part's found once in its
    /// own space (find_receivers over the part alone), then placed, its plane that of its
    /// first triangle placed (as find_receivers takes it).
    void place_receivers(float diameter) {
        const PlacedDraws& placed = *placed_;
        std::vector<std::vector<PartReceivers>> parts;  // per prototype, per part
        for (size_t p = 0; p < placed.placement_count(); ++p) {
            const uint32_t proto = placed.prototype_of(p);
            if (proto >= parts.size()) parts.resize(proto + 1);
            if (!parts[proto].empty() || placed.part_count(proto) == 0) continue;
            uint32_t offset = 0;
            for (size_t k = 0; k < placed.part_count(proto); ++k) {
                const Mesh& m = placed.part_mesh(proto, k);
                TriangleList local;
                size_list(local, m.positions.size(), m.triangle_count(), false, false);
                place_mesh(m, Transform{}, 0, local, 0, 0);
                local.objects = {{0, static_cast<uint32_t>(m.triangle_count())}};
                PartReceivers pr;
                pr.found = find_receivers(local, diameter);
                pr.of.assign(m.triangle_count(), 0);
                for (size_t j = 0; j < pr.found.size(); ++j)
                    for (uint32_t t : pr.found[j].triangles)
                        pr.of[t] = static_cast<uint32_t>(j + 1);
                pr.first = offset;
                offset += static_cast<uint32_t>(pr.found.size());
                parts[proto].push_back(std::move(pr));
            }
        }
        part_receivers_ = std::move(parts);
        for (size_t p = 0; p < placed.placement_count(); ++p) {
            first_receiver_.push_back(static_cast<uint32_t>(receivers_.size()));
            const uint32_t proto = placed.prototype_of(p);
            for (size_t k = 0; k < placed.part_count(proto); ++k) {
                const Mesh& m = placed.part_mesh(proto, k);
                const mat4 to_world = placed.placed_transform(p, k).matrix;
                for (const Receiver& found : part_receivers_[proto][k].found) {
                    const uint32_t t = found.triangles.front();
                    vec3 v[3];
                    for (int c = 0; c < 3; ++c)
                        v[c] = vec3(to_world * vec4(m.positions[m.indices[3 * t + c]], 1.0f));
                    const vec3 cr = glm::cross(v[1] - v[0], v[2] - v[0]);
                    const float area = 0.5f * glm::length(cr);
                    const vec3 n = area > 0.0f ? cr / (2.0f * area) : found.normal;
                    receivers_.push_back({n, glm::dot(n, v[0]), found.area, {}});
                }
            }
        }
    }

    /// The ids of the placement that holds receiver r ([0, 0) for one of the list's).
    std::pair<uint64_t, uint64_t> receiver_ids(size_t r) const {
        if (first_receiver_.empty() || r < first_receiver_.front()) return {0, 0};
        const auto p = static_cast<size_t>(
                           std::upper_bound(first_receiver_.begin(), first_receiver_.end(), r) -
                           first_receiver_.begin()) -
                       1;
        return placed_->ids_of(p);
    }

    /// The receiver triangle `id` of the scene lies in, plus 1 (0: none).
    uint32_t receiver_number(uint32_t id) const {
        if (id < receiver_of_.size()) return receiver_of_[id];
        const auto [p, k, t] = placed_->locate(id);
        const PartReceivers& pr = part_receivers_[placed_->prototype_of(p)][k];
        return pr.of[t] == 0 ? 0 : first_receiver_[p] + pr.first + pr.of[t];
    }

    struct PartReceivers {
        std::vector<Receiver> found;  // in the part's own space
        std::vector<uint32_t> of;     // per triangle of the part: 0, or its receiver plus 1
        uint32_t first = 0;           // its first receiver's place among its placement's
    };

    const PlacedDraws* placed_;  // the frame's instances drawn in place, or null
    std::unique_ptr<AlphaTest> alpha_test_;
    std::vector<Receiver> receivers_;    // the list's, then the placements' in order
    std::vector<uint32_t> receiver_of_;  // per triangle of the list: 0, or its receiver plus 1
    std::vector<std::vector<PartReceivers>> part_receivers_;  // per prototype, per part
    std::vector<uint32_t> first_receiver_;                    // per placement, its first receiver
};

}  // namespace

std::unique_ptr<ShadowTechniqueState> make_planar_shadows(const Scene& scene,
                                                          const TriangleList& list,
                                                          const FrameState& f,
                                                          const std::vector<SamplePattern>& passes,
                                                          int threads, PassMemory* memory) {
    return std::make_unique<PlanarShadows>(scene, list, f, passes, threads, memory);
}

}  // namespace svetlo::raster
