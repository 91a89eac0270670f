// render.shadows "map": shadow maps (Williams, "Casting Curved Shadows on Curved Surfaces",
// SIGGRAPH 1978). Each caster renders the scene's depth from its own position through the
// rasterizer's pass entry point (draw_pass.h), and a sample is lit where it is no farther
// from the caster than the depth the map stores in its direction.
//
//   spot light         one perspective map around the cone
//   point light        a cube map: six perspective maps of 90 degrees (plus a margin)
//   point on an area   a cube map, at resolution / sqrt(N) for N points, so that a light's
//                      maps hold as many texels as one point light's
//   directional light  orthographic maps fitted to what the camera sees: the camera's depth
//                      range is cut into `cascades` slices (the practical split scheme, Zhang
//                      et al. 2006), and each slice's frustum, clipped to the scene, gets a map
//                      (cascaded shadow maps)
//
// Perspective maps store the radial distance from the caster, orthographic ones the depth
// along the light; both in metres (+infinity where nothing was drawn).
//
// Bias: the lookup moves off the surface along its normal by `normal_offset` texels at the
// receiver (normal offset), and a receiver counts as lit up to `bias` metres plus one texel
// times tan(theta) per texel of filter radius behind the stored depth, times `slope_bias`
// (slope-scaled bias). All three at 0 show the acne that bias exists to remove.
//
// Filters (shadow_map_filters.h): `none`, `pcf` and `pcss`; delta lights have no width, and
// PCSS falls back to PCF for them.
//
// The lookup's geometry (where a sample falls on a map, its distance and its bias) is
// shadow_lookup.h's: stated one sample at a time by twin::shadow_lookup, and with SVETLO_SIMD
// computed four samples at once by sse::shadow_lookup4.

#include <algorithm>
#include <array>
#include <bit>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/raster/placed_draws.h"
#include "svetlo/raster/shadow_lookup.h"
#include "svetlo/raster/shadow_map_filters.h"
#include "svetlo/raster/shadow_techniques.h"

namespace svetlo::raster {

namespace {

constexpr uint64_t kMaxShadowMapBytes = uint64_t{2} << 30;  // all maps of a frame together

/// Renders the depth of `list` (the scene's triangles and its instances) through `cam` (res x res)
/// into a map.
DepthMap render_map(const SceneTriangles& list, const CameraMatrices& cam, float tan_half,
                    int threads, PassMemory* memory, const AlphaTest* alpha) {
    DepthMap m;
    m.cam = cam;
    m.view_projection = cam.view_projection();
    m.res = cam.width;
    RenderTargets targets;
    targets.clear(m.res, m.res);
    PipelineState state;  // depth test and write, both sides; alpha's holes let light through
    state.alpha = alpha;
    list.draw(cam, state, targets, sample_pattern(1, 0, 0, 1), threads, memory);
    m.distance = std::move(targets.depth);  // converted in place, bands of rows in parallel
    const float inv = 1.0f / static_cast<float>(m.res);
    constexpr int kRows = 64;
    parallel_indices(static_cast<size_t>((m.res + kRows - 1) / kRows), threads, [&](size_t band) {
        const int y0 = static_cast<int>(band) * kRows, y1 = std::min(m.res, y0 + kRows);
        for (int y = y0; y < y1; ++y) {
            for (int x = 0; x < m.res; ++x) {
                size_t i = targets.index(x, y);
                float key = m.distance[i];
                if (std::isinf(key)) {
                    m.distance[i] = kInfinity;
                } else if (cam.orthographic) {
                    m.distance[i] = cam.near + key * (cam.far - cam.near);  // window z is linear
                } else {
                    // key = -1/w, w the depth along the axis; radial through the texel's centre.
                    float a = (2.0f * (static_cast<float>(x) + 0.5f) * inv - 1.0f) * tan_half;
                    float b = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) * inv) * tan_half;
                    m.distance[i] = (-1.0f / key) * std::sqrt(1.0f + a * a + b * b);
                }
            }
        }
    });
    m.texel = cam.orthographic ? 0.0f : 2.0f * tan_half * inv;
    return m;
}

/// A perspective view from `eye` along `forward`, `tan_half` the tangent of half its square
/// field of view; `up` (not parallel to forward) is the image's top.
CameraMatrices perspective_view(vec3 eye, vec3 forward, vec3 up, float tan_half, int res,
                                float near) {
    CameraMatrices cam;
    cam.view = glm::lookAt(eye, eye + forward, up);
    cam.projection = glm::infinitePerspective(2.0f * std::atan(tan_half), 1.0f, near);
    cam.near = near;
    cam.far = kInfinity;
    cam.width = cam.height = res;
    cam.eye = eye;
    cam.forward = forward;
    return cam;
}

/// The eight corners of the camera's view volume between depths z0 and z1 (world space).
std::array<vec3, 8> frustum_slice(const CameraMatrices& cam, float z0, float z1) {
    const mat4 to_world = glm::inverse(cam.view);
    const float sx = 1.0f / cam.projection[0][0], sy = 1.0f / cam.projection[1][1];
    std::array<vec3, 8> corners;
    for (int k = 0; k < 8; ++k) {
        float z = (k & 4) ? z1 : z0;
        float x = (k & 1) ? 1.0f : -1.0f, y = (k & 2) ? 1.0f : -1.0f;
        vec3 v = cam.orthographic ? vec3(x * sx, y * sy, -z) : vec3(x * sx * z, y * sy * z, -z);
        corners[static_cast<size_t>(k)] = vec3(to_world * vec4(v, 1.0f));
    }
    return corners;
}

/// Every map of one caster, and how a point picks its map.
struct CasterMaps {
    enum class Layout { Single, Cube, Cascades } layout = Layout::Single;
    std::vector<DepthMap> maps;
    std::vector<float> splits;  // cascades: the far camera depth of each slice

    /// The index in `maps` of the map that holds p.
    size_t pick(vec3 p, const ShadowCaster& c, const CameraMatrices& camera) const {
        if (layout == Layout::Cube) {
            vec3 d = p - c.position, a = glm::abs(d);
            int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
            return static_cast<size_t>(2 * axis + (d[axis] < 0.0f ? 1 : 0));
        }
        if (layout == Layout::Cascades) {
            float z = glm::dot(p - camera.eye, camera.forward);
            for (size_t k = 0; k + 1 < maps.size(); ++k) {
                if (z <= splits[k]) return k;
            }
            return maps.size() - 1;
        }
        return 0;
    }
};

class ShadowMaps final : public ShadowTechniqueState {
public:
    ShadowMaps(const Scene& scene, const TriangleList& list, const FrameState& f, int threads,
               PassMemory* memory)
        : settings_(scene.render.shadow_map), camera_(f.cam), memory_(memory) {
        alpha_test_ = std::make_unique<AlphaTest>(f.materials, scene.textures);
        if (alpha_test_->any()) alpha_ = alpha_test_.get();
        const SceneTriangles triangles{list, f.placed.get()};
        const Bounds3 bounds = triangles.bounds();
        const float diameter = scene_diameter(bounds);
        const bool pcss = settings_.filter == ShadowFilter::Pcss;
        const int area_points = pcss ? 0 : scene.render.area_shadow_points;
        area_points_ = std::max(area_points, 1);
        casters_ = shadow_casters(scene, f.lights->set, area_points, 1e-4f * diameter);
        const float near = 1e-4f * diameter;
        // The memory of every map, before any is made.
        uint64_t texels = 0;
        for (const ShadowCaster& c : casters_) {
            uint64_t r = static_cast<uint64_t>(resolution(c));
            texels += r * r *
                      (c.kind == ShadowCaster::Kind::Spot ? 1
                       : c.kind == ShadowCaster::Kind::Directional
                           ? static_cast<uint64_t>(settings_.cascades)
                           : 6);
        }
        // Each map's distances (its depth target, converted in place: 4 bytes a texel).
        if (texels * 4 > kMaxShadowMapBytes) {
            throw Error(scene.path.string(), "render.shadow_map.resolution",
                        "the shadow maps would take " + std::to_string(texels * 4 >> 20) +
                            " MiB (at most " + std::to_string(kMaxShadowMapBytes >> 20) +
                            " MiB); lower the resolution or render.area_shadow_points");
        }
        for (const ShadowCaster& c : casters_)
            maps_.push_back(make_maps(c, triangles, bounds, near, threads));
    }

    float lit(size_t k, const ShadowSample& at) const override {
        const uint32_t first = 0;
        float out = 1.0f;
        lit_many(k, &at, &first, 1, &out);
        return out;
    }

    void lit_many(size_t k, const ShadowSample* samples, const uint32_t* at, size_t count,
                  float* out) const override {
        const ShadowCaster& c = casters_[k];
        const CasterMaps& cm = maps_[k];
        if (cm.maps.size() == 1) {
            lit_on_map(c, cm.maps[0], samples, at, count, out);
            return;
        }
        // A cube's faces or cascades: chunk by chunk, the samples grouped by the map they pick.
        constexpr size_t kChunk = 64;
        uint8_t picked[kChunk];
        uint32_t group[kChunk], slot[kChunk];
        float answer[kChunk];
        for (size_t first = 0; first < count; first += kChunk) {
            const size_t n = std::min(kChunk, count - first);
            for (size_t j = 0; j < n; ++j)
                picked[j] = static_cast<uint8_t>(cm.pick(samples[at[first + j]].p, c, camera_));
            for (size_t map = 0; map < cm.maps.size(); ++map) {
                size_t g = 0;
                for (size_t j = 0; j < n; ++j) {
                    if (picked[j] != map) continue;
                    group[g] = at[first + j];
                    slot[g++] = static_cast<uint32_t>(j);
                }
                if (g == 0) continue;
                lit_on_map(c, cm.maps[map], samples, group, g, answer);
                for (size_t m = 0; m < g; ++m) out[first + slot[m]] = answer[m];
            }
        }
    }

    Image shadow_map_image() const override {
        // Light 0's first caster; a cube map unfolded as a cross: the row -x -z +x +z (turning
        // right from the left), +y above -z and -y below it; each face with its filter margin.
        for (size_t k = 0; k < casters_.size(); ++k) {
            if (casters_[k].source != 0 || maps_[k].maps.empty()) continue;
            const CasterMaps& cm = maps_[k];
            const int r = cm.maps[0].res;
            auto put = [](Image& image, const DepthMap& m, int ox, int oy) {
                for (int y = 0; y < m.res; ++y) {
                    for (int x = 0; x < m.res; ++x) {
                        float d = m.at(x, y);
                        image.at(ox + x, oy + y) = Color(std::isinf(d) ? 0.0f : d);
                    }
                }
            };
            if (cm.layout == CasterMaps::Layout::Cube) {
                Image image(4 * r, 3 * r);
                const int cells[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {3, 1}, {1, 1}};
                for (int face = 0; face < 6; ++face)
                    put(image, cm.maps[static_cast<size_t>(face)], cells[face][0] * r,
                        cells[face][1] * r);
                return image;
            }
            Image image(r * static_cast<int>(cm.maps.size()), r);
            for (size_t i = 0; i < cm.maps.size(); ++i)
                put(image, cm.maps[i], static_cast<int>(i) * r, 0);
            return image;
        }
        return {};
    }

private:
    /// The filtered comparison at a lookup: 1 lit, 0 shadowed.
    float filtered(const ShadowCaster& c, const DepthMap& m, const ShadowLookup& k) const {
        if (!k.on_map) return 1.0f;
        const vec2 px(k.x, k.y);
        const float radius = 0.5f * static_cast<float>(settings_.kernel - 1);
        switch (settings_.filter) {
            case ShadowFilter::None:
                return shadow_compare(m.at(static_cast<int>(px.x), static_cast<int>(px.y)),
                                      k.receiver, settings_.bias + k.slope);
            case ShadowFilter::Pcf:
                return shadow_pcf(m, settings_, px, k.receiver, radius, k.slope);
            case ShadowFilter::Pcss:
                return c.size > 0.0f && !m.cam.orthographic
                           ? shadow_pcss(m, settings_, c.size, px, k.receiver, k.slope)
                           : shadow_pcf(m, settings_, px, k.receiver, radius, k.slope);
        }
        return 1.0f;
    }

    /// lit() for samples[at[m]], m < count, all on map m: each sample's lookup (four at a time
    /// with SSE), then its filter.
    void lit_on_map(const ShadowCaster& c, const DepthMap& m, const ShadowSample* samples,
                    const uint32_t* at, size_t count, float* out) const {
#if SVETLO_SIMD
        for (size_t first = 0; first < count; first += 4) {
            const size_t lanes = std::min<size_t>(4, count - first);
            const ShadowSample* s[4];
            for (size_t L = 0; L < 4; ++L) s[L] = &samples[at[first + std::min(L, lanes - 1)]];
            ShadowLookup k[4];
            sse::shadow_lookup4(settings_, c, m, s, k);
            for (size_t L = 0; L < lanes; ++L) out[first + L] = filtered(c, m, k[L]);
        }
#else
        for (size_t k = 0; k < count; ++k)
            out[k] = filtered(c, m, twin::shadow_lookup(settings_, c, m, samples[at[k]]));
#endif
    }

    int resolution(const ShadowCaster& c) const {
        int r = settings_.resolution;
        if (glm::length(c.normal) > 0.0f && settings_.filter != ShadowFilter::Pcss) {
            auto n = static_cast<float>(area_points_);
            r = std::max(16, static_cast<int>(static_cast<float>(r) / std::sqrt(n)));
        }
        return r;
    }

    CasterMaps make_maps(const ShadowCaster& c, const SceneTriangles& list, const Bounds3& bounds,
                         float near, int threads) const {
        CasterMaps cm;
        const int res = resolution(c);
        const int margin = margin_texels(settings_, res);
        if (c.kind == ShadowCaster::Kind::Directional) {
            cm.layout = CasterMaps::Layout::Cascades;
            make_cascades(c, list, bounds, res, threads, cm);
            return cm;
        }
        const float spread =
            1.0f / (1.0f - 2.0f * static_cast<float>(margin) / static_cast<float>(res));
        if (c.kind == ShadowCaster::Kind::Spot && c.cos_outer > std::cos(radians(80.0f))) {
            float tan_half = std::tan(std::acos(c.cos_outer)) * spread;
            cm.maps.push_back(render_map(
                list,
                perspective_view(c.position, c.direction,
                                 std::abs(c.direction.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0),
                                 tan_half, res, near),
                tan_half, threads, memory_, alpha_));
            return cm;
        }
        cm.layout = CasterMaps::Layout::Cube;
        // +x, -x, +y, -y, +z, -z, each with the top that lets them unfold into a cross
        // (shadow_map_image): the four sideways faces upright, +y and -y joined to -z.
        const vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        const vec3 ups[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {0, 1, 0}, {0, 1, 0}};
        for (int face = 0; face < 6; ++face) {
            cm.maps.push_back(render_map(
                list, perspective_view(c.position, axes[face], ups[face], spread, res, near),
                spread, threads, memory_, alpha_));
        }
        return cm;
    }

    /// Cascaded orthographic maps for a directional caster.
    void make_cascades(const ShadowCaster& c, const SceneTriangles& list, const Bounds3& bounds,
                       int res, int threads, CasterMaps& cm) const {
        const vec3 centre = bounds.center();
        const float radius = 0.5f * std::max(glm::length(bounds.extent()), 1e-6f);
        const vec3 up = std::abs(c.direction.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
        const vec3 eye = centre - c.direction * (2.0f * radius);
        const mat4 view = glm::lookAt(eye, centre, up);
        // The scene's extent in the light's space.
        vec3 lo(kInfinity), hi(-kInfinity);
        for (int k = 0; k < 8; ++k) {
            vec3 corner((k & 1) ? bounds.max.x : bounds.min.x,
                        (k & 2) ? bounds.max.y : bounds.min.y,
                        (k & 4) ? bounds.max.z : bounds.min.z);
            vec3 v = vec3(view * vec4(corner, 1.0f));
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
        const int n = settings_.cascades;
        const float z0 = std::max(camera_.near, 1e-6f * camera_.far), z1 = camera_.far;
        for (int i = 0; i < n; ++i) {
            // The practical split: the mean of the logarithmic and the uniform split.
            auto split = [&](int k) {
                float t = static_cast<float>(k) / static_cast<float>(n);
                return 0.5f * (z0 * std::pow(z1 / z0, t)) + 0.5f * (z0 + (z1 - z0) * t);
            };
            float a = i == 0 ? 0.0f : split(i), b = split(i + 1);
            vec2 flo(kInfinity), fhi(-kInfinity);
            for (vec3 corner : frustum_slice(camera_, std::max(a, z0), b)) {
                vec2 v = vec2(view * vec4(corner, 1.0f));
                flo = glm::min(flo, v);
                fhi = glm::max(fhi, v);
            }
            // The slice clipped to the scene (or the whole scene where they miss each other).
            flo = glm::max(flo, vec2(lo));
            fhi = glm::min(fhi, vec2(hi));
            if (!(flo.x < fhi.x && flo.y < fhi.y)) {
                flo = vec2(lo);
                fhi = vec2(hi);
            }
            // A square map, a margin of the filter's taps around it.
            float side = std::max(std::max(fhi.x - flo.x, fhi.y - flo.y), 1e-6f * radius);
            side *= 1.0f + 2.0f * static_cast<float>(margin_texels(settings_, res)) /
                               static_cast<float>(res);
            vec2 mid = 0.5f * (flo + fhi);
            CameraMatrices cam;
            cam.view = view;
            cam.near = std::max(0.0f, -hi.z - 1e-3f * radius);
            cam.far = -lo.z + 1e-3f * radius;
            cam.projection =
                glm::ortho(mid.x - 0.5f * side, mid.x + 0.5f * side, mid.y - 0.5f * side,
                           mid.y + 0.5f * side, cam.near, cam.far);
            cam.width = cam.height = res;
            cam.eye = eye;
            cam.forward = c.direction;
            cam.orthographic = true;
            DepthMap m = render_map(list, cam, 0.0f, threads, memory_, alpha_);
            m.texel = side / static_cast<float>(res);
            cm.maps.push_back(std::move(m));
            cm.splits.push_back(b);
        }
    }

    ShadowMapSettings settings_;
    int area_points_ = 1;  // casters per light with area
    CameraMatrices camera_;
    PassMemory* memory_;  // while the maps are made
    std::unique_ptr<AlphaTest> alpha_test_;
    const AlphaTest* alpha_ = nullptr;  // when some material has alpha
    std::vector<CasterMaps> maps_;      // per caster
};

}  // namespace

std::unique_ptr<ShadowTechniqueState> make_shadow_maps(const Scene& scene, const TriangleList& list,
                                                       const FrameState& f, int threads,
                                                       PassMemory* memory) {
    return std::make_unique<ShadowMaps>(scene, list, f, threads, memory);
}

}  // namespace svetlo::raster
