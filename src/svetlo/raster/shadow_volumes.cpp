// render.shadows "volume": stencil shadow volumes (Crow, "Shadow Algorithms for Computer
// Graphics", SIGGRAPH 1977; Heidmann 1991; Everitt and Kilgard, "Practical and Robust
// Stenciled Shadow Volumes", 2002).
//
// Per sample pass of the frame: a depth pass from the camera (the same samples as the colour
// pass), then per caster a stencil pass over its volume with the depth test on and depth
// writes off, counting with wrapping; a sample is lit by the caster where the count is 0.
// Per caster, z-fail (Carmack's reverse: back faces up and front faces down where the depth
// test fails), which stays right with the camera inside a volume, wherever a volume may reach
// the near plane; else z-pass (front faces up and back faces down where it passes), the same
// count for less work, with the sides alone (render.shadow_volume.count, auto).
//
// The volume of a caster: every triangle turned toward the caster (flipped when it faces
// away) bounds the region it hides, closed by itself (the near cap), its projection to
// infinity (the far cap) and one quad per edge (the sides); the shadow is the union of those
// regions, and a sample's count is the number of them it lies in. A side shared by two such
// regions with opposite orientation cancels in the count and is not drawn, so a closed,
// consistently wound mesh draws its silhouette edges only (found from the triangle list's
// adjacency), and its triangles facing the caster are left out: its region starts at the
// faces away from the light (as in Doom 3), so no cap lies on a lit surface. Open meshes (a
// quad, a mesh with a hole) keep every triangle, which is why they cast right; their lit
// faces are their own near caps, drawn with a small depth bias (as glPolygonOffset) so that
// they count as behind themselves. A near cap is always drawn as the list's own triangle, in
// its own winding (a flipped one in a second draw with the faces' operations swapped), so
// that clipping and snapping make exactly the triangle the depth pass drew: a reversed
// triangle is clipped into another fan, whose snapped depth can differ by more than any bias.
//
// Points at infinity are homogeneous vertices of weight 0 (TriangleList::w) for a
// perspective camera, whose far plane is at infinity (nothing is clipped behind). An
// orthographic camera's volumes end instead at four scene diameters, and its depth and
// stencil passes use a view whose near and far planes enclose them (as depth clamping would).
#include "svetlo/core/error.h"
#include "svetlo/raster/placed_draws.h"
#include "svetlo/raster/shadow_techniques.h"

namespace svetlo::raster {

namespace {

/// The depth and stencil passes' camera: the frame's, or for an orthographic one the same
/// view with its depth range around the finite volumes (`diameter`: the scene's).
CameraMatrices volume_camera(const CameraMatrices& frame, float diameter) {
    CameraMatrices cam = frame;
    if (cam.orthographic) {
        float reach = 5.0f * diameter;
        cam.near -= reach;
        cam.far += reach;
        const float sx = 1.0f / cam.projection[0][0], sy = 1.0f / cam.projection[1][1];
        const float cx = -cam.projection[3][0] * sx, cy = -cam.projection[3][1] * sy;
        cam.projection = glm::ortho(cx - sx, cx + sx, cy - sy, cy + sy, cam.near, cam.far);
    }
    return cam;
}

/// The pipeline state that draws the volumes into the stencil. z-fail (Carmack's reverse):
/// back faces count up and front faces down where the depth test fails; z-pass (Heidmann):
/// front faces up and back faces down where it passes. Both give the same count unless the
/// camera's near plane cuts a volume, where only z-fail is right; z-pass draws far fewer
/// samples when the volumes stretch far behind the scene (every sample a side covers behind
/// the floor counts in z-fail), so each caster gets z-pass where its volumes cannot reach the
/// near plane.
PipelineState counting_state(VolumeCount count) {
    PipelineState s;
    s.depth_write = false;
    s.write_items = false;
    s.depth_bias = 1.0f / 65536.0f;  // an open surface's own cap lies behind it
    s.stencil.enabled = true;
    if (count == VolumeCount::ZPass) {
        s.stencil.front = {StencilFunc::Always, StencilOp::Keep, StencilOp::Keep,
                           StencilOp::IncrWrap};
        s.stencil.back = {StencilFunc::Always, StencilOp::Keep, StencilOp::Keep,
                          StencilOp::DecrWrap};
    } else {
        s.stencil.back = {StencilFunc::Always, StencilOp::Keep, StencilOp::IncrWrap,
                          StencilOp::Keep};
        s.stencil.front = {StencilFunc::Always, StencilOp::Keep, StencilOp::DecrWrap,
                           StencilOp::Keep};
    }
    return s;
}

/// A list whose shadow volumes are made: its triangles, and per object whether it is closed
/// (closed_objects), per triangle its object.
struct Occluders {
    const TriangleList& list;
    std::vector<char> closed;
    std::vector<uint32_t> object_of;

    explicit Occluders(const TriangleList& l)
        : list(l), closed(closed_objects(l)), object_of(l.triangle_count()) {
        for (size_t o = 0; o < l.objects.size(); ++o)
            for (uint32_t t = l.objects[o].first; t < l.objects[o].end; ++t)
                object_of[t] = static_cast<uint32_t>(o);
    }
};

class ShadowVolumes final : public StencilMasks {
public:
    ShadowVolumes(const Scene& scene, const TriangleList& list, const FrameState& f,
                  const std::vector<SamplePattern>& passes, int threads, PassMemory* memory)
        : diameter_(scene_diameter(SceneTriangles{list, f.placed.get()}.bounds())) {
        // The scene's list, and its instances drawn in place (their volumes made batch by
        // batch, each placement's parts with their own adjacency).
        const SceneTriangles scene_triangles{list, f.placed.get()};
        const PlacedDraws* placed = f.placed.get();
        casters_ = shadow_casters(scene, f.lights->set, scene.render.area_shadow_points,
                                  1e-4f * diameter_);
        // (The depth and stencil targets: 4 + 1 bytes per sample of a pass.)
        reserve(scene, f.cam.width, f.cam.height, passes, 5, "shadow volumes' masks");
        const Occluders own(list);
        object_bounds_.resize(list.objects.size());
        for (size_t o = 0; o < list.objects.size(); ++o) {
            for (uint32_t t = list.objects[o].first; t < list.objects[o].end; ++t) {
                for (int k = 0; k < 3; ++k)
                    object_bounds_[o].extend(list.positions[list.indices[3 * t + k]]);
            }
        }
        if (placed)
            object_bounds_.insert(object_bounds_.end(), placed->boxes().begin(),
                                  placed->boxes().end());
        const CameraMatrices cam = volume_camera(f.cam, diameter_);
        PipelineState depth_state;
        depth_state.cull = f.cull;
        const PipelineState zfail = counting_state(VolumeCount::ZFail);
        const PipelineState zpass = counting_state(VolumeCount::ZPass);
        std::vector<std::pair<TriangleList, TriangleList>> volumes;  // the list's, per caster
        std::vector<char> caps;                                      // per caster
        for (const ShadowCaster& c : casters_) {
            const VolumeCount count = scene.render.shadow_teaching.volume_count;
            bool use_zfail = count == VolumeCount::ZFail ||
                             (count == VolumeCount::Auto &&
                              (cam.orthographic || near_plane_may_be_shadowed(c, f.cam)));
            zfail_.push_back(use_zfail ? 1 : 0);
            // z-pass counts no cap: a near cap is a triangle of the scene, never nearer than
            // what the depth pass kept there (and drawn a little farther), and the far caps
            // lie at infinity. It draws the sides alone, unless the depth pass culled back
            // faces (an open mesh seen from behind is then not in the depth buffer, and its
            // caps count).
            caps.push_back(use_zfail || f.cull != CullMode::None ? 1 : 0);
            volumes.push_back(volume(own, c, cam.orthographic, caps.back() != 0));
        }
        for (const SamplePattern& sp : passes) {
            RenderTargets targets;
            targets.clear(width_, height_, sp.count, true);
            scene_triangles.draw(cam, depth_state, targets, sp, threads, memory);
            for (size_t k = 0; k < casters_.size(); ++k) {
                std::fill(targets.stencil.begin(), targets.stencil.end(), uint8_t{0});
                const PipelineState& state = zfail_[k] ? zfail : zpass;
                // The flipped near caps are drawn as the list's own triangles, in their own
                // winding, with the faces' operations swapped: rasterized exactly as the
                // depth pass drew them.
                PipelineState flipped = state;
                std::swap(flipped.stencil.front, flipped.stencil.back);
                auto draw = [&](const std::pair<TriangleList, TriangleList>& v) {
                    draw_samples(v.first, cam, state, targets, threads, sp, memory);
                    if (!v.second.indices.empty())
                        draw_samples(v.second, cam, flipped, targets, threads, sp, memory);
                };
                draw(volumes[k]);
                if (placed) {  // (a placement out of view may cast into it: all of them)
                    placed->for_each_batch(
                        nullptr, threads, scene_triangles.scratch,
                        [&](const TriangleList& batch, const std::vector<uint32_t>&,
                            const std::vector<size_t>&) {
                            draw(volume(Occluders(batch), casters_[k], cam.orthographic,
                                        caps[k] != 0));
                        });
                }
                std::vector<uint8_t> lit(targets.stencil.size());
                for (size_t i = 0; i < lit.size(); ++i) lit[i] = targets.stencil[i] == 0 ? 1 : 0;
                lit_[k].push_back(std::move(lit));
                if (k == 0 && stencil_samples_ == 0) {  // (for the debug AOV)
                    stencil_ = targets.stencil;
                    stencil_samples_ = targets.samples;
                }
            }
        }
    }

    /// The signed stencil count per pixel, averaged over its samples: caster 0's, of the
    /// first sample pass.
    Image stencil_image() const override {
        if (stencil_samples_ == 0) return {};
        Image image(width_, height_);
        const int S = stencil_samples_;
        for (int j = 0; j < height_; ++j) {
            for (int i = 0; i < width_; ++i) {
                float sum = 0.0f;
                for (int s = 0; s < S; ++s) {
                    sum += static_cast<float>(
                        static_cast<int8_t>(stencil_[frame_sample(width_, S, i, j, s)]));
                }
                image.at(i, j) = Color(sum / static_cast<float>(S));
            }
        }
        return image;
    }

private:
    /// Whether a volume of caster c may contain a point of the camera's near-plane rectangle:
    /// some object's bounds meet the region between the caster and that rectangle (a pyramid
    /// with the light at its apex, or a prism toward a directional light; Everitt and
    /// Kilgard 2002). Conservative: true may be wrong, false never is.
    bool near_plane_may_be_shadowed(const ShadowCaster& c, const CameraMatrices& cam) const {
        const mat4 to_world = glm::inverse(cam.view);
        const float sx = 1.0f / cam.projection[0][0], sy = 1.0f / cam.projection[1][1];
        vec3 corner[4];
        const float xs[4] = {-1, 1, 1, -1}, ys[4] = {-1, -1, 1, 1};
        for (int k = 0; k < 4; ++k)
            corner[k] = vec3(to_world *
                             vec4(xs[k] * sx * cam.near, ys[k] * sy * cam.near, -cam.near, 1.0f));
        const bool directional = c.kind == ShadowCaster::Kind::Directional;
        const float reach = 2.0f * diameter_ + 1.0f;
        // Toward the light from the rectangle's centre: a point inside the region.
        const vec3 centre = 0.25f * (corner[0] + corner[1] + corner[2] + corner[3]);
        const vec3 inside =
            directional ? centre - c.direction * reach : 0.5f * (centre + c.position);
        std::vector<vec4> planes;  // (n, d): n . x + d >= 0 inside
        auto plane = [&](vec3 a, vec3 b, vec3 q) {
            vec3 n = glm::cross(b - a, q - a);
            if (!(glm::dot(n, n) > 0.0f)) return;
            if (glm::dot(n, inside - a) < 0.0f) n = -n;
            planes.push_back(vec4(n, -glm::dot(n, a)));
        };
        for (int k = 0; k < 4; ++k) {
            vec3 a = corner[k], b = corner[(k + 1) % 4];
            plane(a, b, directional ? a - c.direction : c.position);
        }
        plane(corner[0], corner[1], corner[2]);  // the near plane's side toward the light
        if (!directional) {
            // Nothing behind the light: the plane through it facing the rectangle.
            vec3 n = centre - c.position;
            if (glm::dot(n, n) > 0.0f) planes.push_back(vec4(n, -glm::dot(n, c.position)));
        }
        for (const Bounds3& b : object_bounds_) {
            if (b.empty()) continue;
            bool separated = false;
            for (const vec4& pl : planes) {
                // The box's corner farthest along the plane's normal is outside: all are.
                vec3 far(pl.x >= 0.0f ? b.max.x : b.min.x, pl.y >= 0.0f ? b.max.y : b.min.y,
                         pl.z >= 0.0f ? b.max.z : b.min.z);
                if (glm::dot(vec3(pl), far) + pl.w < 0.0f) {
                    separated = true;
                    break;
                }
            }
            if (!separated) return true;
        }
        return false;
    }

    /// The triangles of `list` that bound a shadow region of caster c (`used`), and which of
    /// them face away from it and so are flipped (`flipped`).
    void boundary_triangles(const Occluders& in, const ShadowCaster& c, std::vector<char>& used,
                            std::vector<char>& flipped) const {
        const TriangleList& list = in.list;
        const bool directional = c.kind == ShadowCaster::Kind::Directional;
        const size_t T = list.triangle_count();
        used.assign(T, 0);
        flipped.assign(T, 0);
        for (size_t t = 0; t < T; ++t) {
            const uint32_t* idx = &list.indices[3 * t];
            vec3 a = list.positions[idx[0]], b = list.positions[idx[1]],
                 cc = list.positions[idx[2]];
            vec3 normal = glm::cross(b - a, cc - a);
            if (!(glm::dot(normal, normal) > 0.0f)) continue;  // no area: bounds nothing
            float side =
                directional ? -glm::dot(normal, c.direction) : glm::dot(normal, c.position - a);
            bool facing = side > 0.0f;
            // A closed object's region is bounded by its faces away from the caster (the
            // lit faces are then on no volume's boundary, and no rounding can shadow them).
            if (facing && in.closed[in.object_of[t]]) continue;
            used[t] = 1;
            flipped[t] = facing ? 0 : 1;
        }
    }

    /// Far caps at infinity as a fan: the far caps of an object's regions, seen from the
    /// caster, cover the directions its silhouette encloses; the stencil counts winding
    /// numbers, so a fan from one direction A over the object's side edges counts the same
    /// as one far cap per triangle, with a triangle per side edge instead of one per cap.
    /// It holds where every direction from the caster to the object lies within 90 degrees
    /// of A (the fan's triangles are then the small spherical ones): a point or spot caster
    /// outside the object. Returns each object's apex, A as a vertex at infinity appended to
    /// `v`, or kOpen where it takes one far cap per triangle (and for finite volumes).
    std::vector<uint32_t> far_cap_apexes(const Occluders& in, const ShadowCaster& c, bool finite,
                                         const std::vector<char>& used, TriangleList& v) const {
        const TriangleList& list = in.list;
        std::vector<uint32_t> apex(list.objects.size(), TriangleList::kOpen);
        if (finite || c.kind == ShadowCaster::Kind::Directional) return apex;
        for (size_t o = 0; o < list.objects.size(); ++o) {
            const PrimitiveRange r = list.objects[o];
            vec3 centre(0.0f);
            float count = 0.0f;
            for (uint32_t t = r.first; t < r.end; ++t) {
                if (!used[t]) continue;
                for (int k = 0; k < 3; ++k) centre += list.positions[list.indices[3 * t + k]];
                count += 3.0f;
            }
            if (count == 0.0f) continue;
            const vec3 a = centre / count - c.position;
            bool within = glm::dot(a, a) > 0.0f;
            for (uint32_t t = r.first; t < r.end && within; ++t) {
                for (int k = 0; k < 3 && used[t]; ++k) {
                    vec3 d = list.positions[list.indices[3 * t + k]] - c.position;
                    within = within && glm::dot(d, a) > 1e-3f * glm::length(d) * glm::length(a);
                }
            }
            if (!within) continue;
            apex[o] = static_cast<uint32_t>(v.positions.size());
            v.positions.push_back(a);
            v.w.push_back(0.0f);
        }
        return apex;
    }

    /// The shadow volume of caster c over every triangle of `list`: its sides, far caps and
    /// unflipped near caps, and apart the flipped near caps in the list's winding (with
    /// `caps` false, the sides alone).
    std::pair<TriangleList, TriangleList> volume(const Occluders& in, const ShadowCaster& c,
                                                 bool finite, bool caps) const {
        const TriangleList& list = in.list;
        const size_t n = list.positions.size();
        const bool directional = c.kind == ShadowCaster::Kind::Directional;
        TriangleList v;
        v.positions = list.positions;
        // The extruded vertices follow the finite ones: n of them (one for a directional light
        // with points at infinity, which all meet in its direction).
        const bool one_direction = directional && !finite;
        const size_t extruded = one_direction ? 1 : n;
        v.positions.resize(n + extruded);
        for (size_t i = 0; i < extruded; ++i) {
            vec3 d = directional ? c.direction : list.positions[i] - c.position;
            if (finite) {
                float len = glm::length(d);
                d = len > 0.0f ? list.positions[i] + d * (4.0f * diameter_ / len)
                               : list.positions[i];
            }
            v.positions[n + i] = d;
        }
        if (!finite) {
            v.w.assign(n + extruded, 1.0f);
            std::fill(v.w.begin() + static_cast<std::ptrdiff_t>(n), v.w.end(), 0.0f);
        }
        auto far = [&](uint32_t i) { return static_cast<uint32_t>(n + (one_direction ? 0 : i)); };
        const size_t T = list.triangle_count();
        std::vector<char> used, flipped;
        boundary_triangles(in, c, used, flipped);
        const std::vector<uint32_t> apex = far_cap_apexes(in, c, finite, used, v);
        TriangleList flipped_caps;
        flipped_caps.positions = list.positions;
        auto add = [&](uint32_t a, uint32_t b, uint32_t cc) {
            v.indices.insert(v.indices.end(), {a, b, cc});
        };
        for (size_t t = 0; t < T; ++t) {
            if (!used[t]) continue;
            const uint32_t fan = apex[in.object_of[t]];
            uint32_t o[3] = {list.indices[3 * t], list.indices[3 * t + 1], list.indices[3 * t + 2]};
            if (flipped[t]) {
                if (caps) flipped_caps.indices.insert(flipped_caps.indices.end(), o, o + 3);
                std::swap(o[1], o[2]);
            } else if (caps) {
                add(o[0], o[1], o[2]);  // near cap, facing the caster
            }
            if (caps && fan == TriangleList::kOpen)
                add(far(o[0]), far(o[2]), far(o[1]));  // far cap, facing away
            for (int e = 0; e < 3; ++e) {
                // Edge e of the original triangle runs from vertex e to e + 1.
                uint32_t nb = list.neighbour[3 * t + static_cast<size_t>(e)];
                const bool cancels =
                    nb != TriangleList::kOpen && used[nb] && flipped[nb] == flipped[t];
                // The fan closes this object's far caps alone: an edge it shares with another
                // object (their sides cancel) is on its boundary all the same.
                const bool fan_edge =
                    fan != TriangleList::kOpen && (!cancels || in.object_of[nb] != in.object_of[t]);
                if (cancels && !fan_edge) continue;
                uint32_t from = list.indices[3 * t + static_cast<size_t>(e)];
                uint32_t to = list.indices[3 * t + static_cast<size_t>((e + 1) % 3)];
                if (flipped[t]) std::swap(from, to);
                if (!cancels) {
                    add(from, far(from), far(to));  // the side, facing out of the region
                    add(from, far(to), to);
                }
                if (caps && fan_edge) add(fan, far(to), far(from));  // the far caps' fan
            }
        }
        for (TriangleList* l : {&v, &flipped_caps}) {
            l->material.assign(l->indices.size() / 3, 0);
            l->normals.assign(l->positions.size(), vec3(0.0f));
            l->uvs.assign(l->positions.size(), vec2(0.0f));
        }
        return {std::move(v), std::move(flipped_caps)};
    }

    float diameter_ = 1.0f;
    std::vector<Bounds3> object_bounds_;  // per object of the list, then per placement
    std::vector<char> zfail_;             // per caster: counted with z-fail
    std::vector<uint8_t> stencil_;        // caster 0's counts (the first sample pass)
    int stencil_samples_ = 0;             // its samples per pixel
};

}  // namespace

std::unique_ptr<ShadowTechniqueState> make_shadow_volumes(const Scene& scene,
                                                          const TriangleList& list,
                                                          const FrameState& f,
                                                          const std::vector<SamplePattern>& passes,
                                                          int threads, PassMemory* memory) {
    return std::make_unique<ShadowVolumes>(scene, list, f, passes, threads, memory);
}

}  // namespace svetlo::raster
