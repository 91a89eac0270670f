#include "svetlo/raster/shadow_masks.h"

#include <algorithm>
#include <cstdlib>

#include "svetlo/core/error.h"
#include "svetlo/raster/fragment.h"
#include "svetlo/raster/shadow_techniques.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo::raster {

std::unique_ptr<ShadowTechniqueState> make_shadow_technique(
    const Scene& scene, const TriangleList& list, const FrameState& f,
    const std::vector<SamplePattern>& passes, int threads, PassMemory* memory) {
    switch (scene.render.shadows) {
        case ShadowTechnique::None:
            return nullptr;
        case ShadowTechnique::Raytraced:
            return make_raytraced_shadows(scene, list, f, f.caches, threads, memory);
        case ShadowTechnique::Map:
            return make_shadow_maps(scene, list, f, threads, memory);
        case ShadowTechnique::Volume:
            return make_shadow_volumes(scene, list, f, passes, threads, memory);
        case ShadowTechnique::Planar:
            return make_planar_shadows(scene, list, f, passes, threads, memory);
    }
    return nullptr;
}

void StencilMasks::reserve(const Scene& scene, int width, int height,
                           const std::vector<SamplePattern>& passes, uint64_t working,
                           const char* what) {
    constexpr uint64_t kMaxMaskBytes = uint64_t{2} << 30;  // every caster's mask, every pass
    width_ = width;
    height_ = height;
    samples_per_pass_.clear();
    uint64_t samples = 0;
    for (const SamplePattern& sp : passes) samples_per_pass_.push_back(sp.count);
    for (const SamplePattern& sp : passes)
        samples += static_cast<uint64_t>(width) * static_cast<uint64_t>(height) *
                   static_cast<uint64_t>(sp.count);
    const uint64_t bytes = samples * (casters_.size() + working);
    if (bytes > kMaxMaskBytes) {
        throw Error(scene.path.string(), "render.area_shadow_points",
                    std::string("the ") + what + " would take " + std::to_string(bytes >> 20) +
                        " MiB (at most " + std::to_string(kMaxMaskBytes >> 20) +
                        " MiB); lower render.spp or render.area_shadow_points");
    }
    lit_.assign(casters_.size(), {});
}

float StencilMasks::lit(size_t k, const ShadowSample& at) const {
    const std::vector<uint8_t>& mask = lit_[k][static_cast<size_t>(at.pass)];
    const int samples = samples_per_pass_[static_cast<size_t>(at.pass)];
    return static_cast<float>(mask[frame_sample(width_, samples, at.i, at.j, at.s)]);
}

Image StencilMasks::mask_image() const {
    if (casters_.empty()) return Image(width_, height_);  // nothing casts: no shadow
    Image image(width_, height_);
    int total = 0;
    for (size_t pass = 0; pass < samples_per_pass_.size(); ++pass) {
        const int S = samples_per_pass_[pass];
        const std::vector<uint8_t>& mask = lit_[0][pass];
        for (int j = 0; j < height_; ++j)
            for (int i = 0; i < width_; ++i)
                for (int s = 0; s < S; ++s)
                    image.at(i, j) += Color(mask[frame_sample(width_, S, i, j, s)] ? 0.0f : 1.0f);
        total += S;
    }
    for (Color& c : image.pixels) c /= static_cast<float>(std::max(total, 1));
    return image;
}

float scene_diameter(const Bounds3& bounds) {
    return bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-6f);
}

namespace {

/// The world point of a sample with screen barycentrics l of vertices 1 and 2.
inline vec3 sample_point(const ClipVertex& A, const ClipVertex& B, const ClipVertex& C, vec2 l) {
    const Weights w = perspective_weights(l, A, B, C);
    return w.b[0] * A.world + w.b[1] * B.world + w.b[2] * C.world;
}

/// Which side of a surface the camera sees (a copy of the frame's camera, which loops keep
/// in registers).
struct Viewer {
    vec3 eye, forward;
    bool orthographic;
    explicit Viewer(const FrameState& f)
        : eye(f.cam.eye), forward(f.cam.forward), orthographic(f.cam.orthographic) {}
    /// Whether it sees the side of unit normal ng at p (the sign of ng . wo, wo not made unit).
    bool sees_front(vec3 ng, vec3 p) const {
        const vec3 toward_eye = orthographic ? -forward : eye - p;
        return glm::dot(ng, toward_eye) >= 0.0f;
    }
};

/// The surfaces (ShadowSample) of a run of one sample per pixel: the samples index[0..r) of
/// the tile, r >= 8, consecutive pixels of one row and one triangle, drawn by the general
/// rasterizer (not a small triangle's kept weights). Returns r, or 0 where there is no such
/// run (then the samples are made one by one). Lane by lane (TriangleEdges::run_weights,
/// sample_point, Viewer: the numbers of the loop in fill_masks), which the compiler
/// vectorizes.
size_t surfaces_of_run(const FrameState& f, const Tile& tile, int pass, const TileBuffers& buf,
                       const uint32_t* index, size_t left, bool left_weights,
                       const SamplePattern& sp, ShadowSample* out) {
    constexpr size_t kMinRun = 8;
    const int tw = tile.x1 - tile.x0;
    const uint32_t first = index[0], id = buf.tri[first];
    const int px = static_cast<int>(first % static_cast<uint32_t>(tw));
    const size_t most = std::min(left, static_cast<size_t>(tw - px));
    size_t r = 1;
    while (r < most && index[r] == first + r && buf.tri[first + r] == id) ++r;
    if (r < kMinRun) return 0;
    const SetupTriangle& t = f.tri(id);
    if (left_weights && t.small) return 0;
    const ClipVertex& A = f.vertex(t.v[0]);
    const ClipVertex& B = f.vertex(t.v[1]);
    const ClipVertex& C = f.vertex(t.v[2]);
    const uint32_t triangle = f.source(id);
    const int py = tile.y0 + static_cast<int>(first / static_cast<uint32_t>(tw));
    alignas(32) float l1[kTile], l2[kTile], p[3][kTile], side[kTile];
    TriangleEdges(t).run_weights(static_cast<int64_t>(tile.x0 + px) * kSubpixel + sp.ox[0],
                                 static_cast<int64_t>(py) * kSubpixel + sp.oy[0],
                                 static_cast<int>(r), l1, l2);
    const vec3 ng = face_normal(t, A, B, C);
    const Viewer viewer(f);
    for (size_t j = 0; j < r; ++j) {
        const vec3 q = sample_point(A, B, C, vec2(l1[j], l2[j]));
        side[j] = viewer.sees_front(ng, q) ? 1.0f : -1.0f;
        for (int c = 0; c < 3; ++c) p[c][j] = q[c];
    }
    for (size_t j = 0; j < r; ++j) {
        ShadowSample& at = out[j];
        at.pass = pass;
        at.i = tile.x0 + px + static_cast<int>(j);
        at.j = py;
        at.s = 0;
        at.p = vec3(p[0][j], p[1][j], p[2][j]);
        at.n = side[j] > 0.0f ? ng : -ng;
        at.triangle = triangle;
    }
    return r;
}

}  // namespace

namespace {

/// The samples of the tile that need a mask, their indices into scratch.index, counted: the
/// covered ones, and for a screen-space technique those not lit by every caster (where every
/// caster lights a sample, V is 1 whether it faces them or not).
size_t samples_to_mask(const FrameState& f, const Tile& tile, int S, size_t samples,
                       bool needs_surface, const TileBuffers& buf, MaskScratch& scratch) {
    size_t n = 0;
    if (needs_surface) {
        for (size_t i = 0; i < samples; ++i) {
            if (buf.tri[i] != kNone) scratch.index[n++] = static_cast<uint32_t>(i);
        }
    } else {
        size_t i = 0;
        for (int py = tile.y0; py < tile.y1; ++py) {
            for (int px = tile.x0; px < tile.x1; ++px) {
                const size_t in_frame = frame_sample(f.cam.width, S, px, py, 0);
                for (int s = 0; s < S; ++s, ++i) {
                    if (buf.tri[i] == kNone) continue;
                    bool all_lit = true;
                    for (const uint8_t* mask : scratch.masks)
                        all_lit = all_lit && mask[in_frame + static_cast<size_t>(s)];
                    if (!all_lit) scratch.index[n++] = static_cast<uint32_t>(i);
                }
            }
        }
    }
    return n;
}

/// The surfaces of the first n samples listed in scratch.index: point, normal toward the
/// viewer and triangle, into found[0, n).
void surfaces_to_mask(const FrameState& f, const Tile& tile, const SamplePattern& sp, int pass,
                      bool left_weights, const TileBuffers& buf, MaskScratch& scratch, size_t n,
                      ShadowSample* found) {
    const int S = sp.count;
    const int tw = tile.x1 - tile.x0;
    EdgeCache edges(f);
    const Viewer viewer(f);
    uint32_t normal_of = kNone;  // the triangle whose unit normal ng is
    vec3 ng(0.0f);               // and its unit normal
    for (size_t m = 0; m < n; ++m) {
        // One sample per pixel: a run of one triangle's pixels along a row, lane by lane.
        if (S == 1) {
            const size_t run = surfaces_of_run(f, tile, pass, buf, scratch.index.data() + m, n - m,
                                               left_weights, sp, found + m);
            if (run > 0) {
                m += run - 1;
                continue;
            }
        }
        // The samples' triangles and their vertices are scattered over the frame's (a
        // triangle covers a pixel or two): fetch ahead, the triangle first and its vertices
        // once it has arrived.
        constexpr size_t kAheadTriangle = 16, kAheadVertices = 8;
        if (m + kAheadTriangle < n)
            __builtin_prefetch(&f.tri(buf.tri[scratch.index[m + kAheadTriangle]]));
        if (m + kAheadVertices < n) {
            const SetupTriangle& ahead = f.tri(buf.tri[scratch.index[m + kAheadVertices]]);
            for (int v = 0; v < 3; ++v) __builtin_prefetch(&f.vertex(ahead.v[v]));
        }
        const size_t i = scratch.index[m];
        const uint32_t id = buf.tri[i];
        const size_t pixel = i / static_cast<size_t>(S);
        const int px = tile.x0 + static_cast<int>(pixel % static_cast<size_t>(tw)),
                  py = tile.y0 + static_cast<int>(pixel / static_cast<size_t>(tw));
        const int s = static_cast<int>(i % static_cast<size_t>(S));
        ShadowSample& at = found[m];
        at.pass = pass;
        at.i = px;
        at.j = py;
        at.s = s;
        const SetupTriangle& t = f.tri(id);
        const ClipVertex& A = f.vertex(t.v[0]);
        const ClipVertex& B = f.vertex(t.v[1]);
        const ClipVertex& C = f.vertex(t.v[2]);
        if (id != normal_of) {
            normal_of = id;
            ng = face_normal(t, A, B, C);
        }
        const vec2 l = left_weights && t.small
                           ? vec2(buf.l1[i], buf.l2[i])
                           : edges.of(id).weights(static_cast<int64_t>(px) * kSubpixel + sp.ox[s],
                                                  static_cast<int64_t>(py) * kSubpixel + sp.oy[s]);
        at.p = sample_point(A, B, C, l);
        at.n = viewer.sees_front(ng, at.p) ? ng : -ng;
        at.triangle = f.source(id);
    }
}

/// Each light's visibility of the n samples found: the mean over its casters of the lit
/// fraction each answers (lit_many), written into buf.visibility at the samples' places.
void visibility_of(const ShadowTechniqueState& technique, const ShadowSample* found, size_t n,
                   size_t samples, TileBuffers& buf, MaskScratch& scratch) {
    const std::vector<ShadowCaster>& casters = technique.casters();
    // Source by source (shadow_casters groups a source's casters together), so that the sums
    // take memory for one source's samples, whatever the number of lights.
    scratch.sum.resize(n);
    scratch.count.resize(n);
    for (size_t k = 0; k < casters.size();) {
        const size_t source = casters[k].source;
        std::fill(scratch.sum.begin(), scratch.sum.end(), 0.0f);
        std::fill(scratch.count.begin(), scratch.count.end(), 0.0f);
        for (; k < casters.size() && casters[k].source == source; ++k) {
            const ShadowCaster& c = casters[k];
            // The samples it lights from the front, listed without a branch (each index
            // written, the count moved on where it faces); with an occluder cube, those it
            // shows clear are lit at once.
            scratch.facing.resize(n);
            size_t facing = 0;
            if (const OccluderCube* cube = technique.occluders(k)) {
                for (size_t m = 0; m < n; ++m) {
                    const ShadowSample& s = found[m];
                    if (!c.faces(s.p, s.n)) continue;
                    if (cube->clear(s.p, s.n, s.triangle)) {
                        scratch.sum[m] += 1.0f;
                        scratch.count[m] += 1.0f;
                    } else {
                        scratch.facing[facing++] = static_cast<uint32_t>(m);
                    }
                }
            } else {
                for (size_t m = 0; m < n; ++m) {
                    scratch.facing[facing] = static_cast<uint32_t>(m);
                    facing += c.faces(found[m].p, found[m].n) ? 1 : 0;
                }
            }
            scratch.facing.resize(facing);
            scratch.lit.resize(facing);
            technique.lit_many(k, found, scratch.facing.data(), facing, scratch.lit.data());
            for (size_t m = 0; m < facing; ++m) {
                scratch.sum[scratch.facing[m]] += scratch.lit[m];
                scratch.count[scratch.facing[m]] += 1.0f;
            }
        }
        float* visibility = buf.visibility.data() + source * samples;
        for (size_t m = 0; m < n; ++m) {
            if (scratch.count[m] > 0.0f)
                visibility[scratch.index[m]] = scratch.sum[m] / scratch.count[m];
        }
    }
}

}  // namespace

void fill_masks(const ShadowTechniqueState& technique, const FrameState& f, const Tile& tile,
                const SamplePattern& sp, int pass, bool small_left_weights, TileBuffers& buf,
                MaskScratch& scratch) {
    const int S = sp.count;
    const int tw = tile.x1 - tile.x0;
    const size_t pixels = static_cast<size_t>(tw) * (tile.y1 - tile.y0);
    const size_t samples = pixels * static_cast<size_t>(S);
    const size_t sources = f.lights->set.sources().size();
    buf.visibility.assign(sources * samples, 1.0f);
    const std::vector<ShadowCaster>& casters = technique.casters();
    if (casters.empty()) return;
    const bool needs_surface = technique.needs_surface();
    // A screen-space technique's masks, read directly for the samples every caster lights.
    scratch.masks.clear();
    for (size_t k = 0; k < casters.size() && !needs_surface; ++k)
        scratch.masks.push_back(technique.screen_mask(k, pass));
    // First the samples that need a mask, with their surface; then each caster answers for
    // all of them at once (lit_many), so that their lookups overlap.
    // (Written in place: a sample made on the stack and copied would be read back before its
    // stores had landed.)
    std::vector<ShadowSample>& found = scratch.samples;
    if (found.size() < samples) {
        found.resize(samples);
        scratch.index.resize(samples);
    }
    const size_t n = samples_to_mask(f, tile, S, samples, needs_surface, buf, scratch);
    surfaces_to_mask(f, tile, sp, pass, small_left_weights && S == 1, buf, scratch, n,
                     found.data());
    visibility_of(technique, found.data(), n, samples, buf, scratch);
}

}  // namespace svetlo::raster
