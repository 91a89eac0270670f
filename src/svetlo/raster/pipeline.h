// The rasterization pipeline's internal state, shared by its stages (one file each):
//
//   vertex_stage.cpp    stage 2: model, view, projection; projection and snapping; Gouraud
//   clipper.cpp         stage 3: clipping in homogeneous coordinates
//   setup_binning.cpp   stages 3-4: setup (area, facing, culling, bounds) and binning in tiles
//   depth_pass_avx2.cpp a depth-only pass's setup and rasterization with AVX2
//   stencil_count_avx2.cpp  the stencil count with AVX2
//   small_triangle.h    a small triangle's edges and depth plane, and a depth-only pass's record
//   rasterize.cpp       stage 5: edge functions and the depth test, per tile
//   rasterize_stencil.cpp stage 5 with the stencil on or depth writes off: the per-sample loop
//   stencil_count.cpp   a shadow volume's stencil count over a rectangle of pixels
//   fragment.cpp        stage 6: shading of the visible samples, by mode
//   fast_shading.cpp    stage 6's SIMD fast path (simd_kernel.inc)
//   resolve.cpp         stage 7: the mean of the samples, the AOVs, and the wireframe
//   draw_pass.cpp       the entry point: a draw list through a camera, a state, into targets
//   placed_draws.cpp    instances drawn in place: placements in batches, the visibility pass
//
// raster_engine.cpp (stage 1, tessellation, and the frame as a sequence of passes) and the
// passes of the shadow techniques build on these. Not a public interface: include
// draw_pass.h or raster_engine.h instead.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "svetlo/core/large_array.h"
#include "svetlo/core/parallel.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/clipper.h"
#include "svetlo/raster/draw_pass.h"
#include "svetlo/raster/edge_function.h"
#include "svetlo/raster/raster_lights.h"
#include "svetlo/raster/simd_shading.h"
#include "svetlo/raster/small_triangle.h"
#include "svetlo/scene/renderer.h"
#include "svetlo/shading/mipmap.h"

namespace svetlo::raster {

class PlacedDraws;

constexpr int kTile = 64;                // pixels per side of a binning tile
constexpr int kMaxSamplesPerPass = 16;   // samples per pixel held at once; more take passes
constexpr size_t kChunk = 4096;          // triangles per unit of parallel setup and binning
constexpr float kGuardPixels = 4096.0f;  // guard band beyond each side of the viewport
constexpr uint32_t kNone = ~0u;          // no triangle in a sample
constexpr uint32_t kExtra = 1u << 31;    // a vertex made by clipping (chunk-local until fixed up)
constexpr uint64_t kMaxTriangles = 1u << 25;  // 33.5 M triangles: about 6 GiB of pipeline state

using Mode = ShadingMode;

/// The overdraw view: a pixel's value is the fragments rasterized there, divided by this.
constexpr float kOverdrawPerUnit = 8.0f;

/// A vertex after projection: fixed-point pixels and the depth key (setup_triangle).
struct ScreenVertex {
    int32_t x = 0, y = 0;
    float z = 0.0f;
    // 1 when inside every clip plane: a triangle of three such vertices skips clipping.
    uint32_t inside = 0;
};

/// A triangle after clipping, projection and snapping, ready to rasterize: one cache line,
/// since the tiles stream through a million of them.
struct SetupTriangle {
    int32_t x[3], y[3];  // fixed-point pixels, wound so that the area is positive
    float z[3];          // depth key, affine in screen space, smaller is nearer (project)
    uint32_t v[3];       // vertex indices, in the wound order
    // Pixels [bx0, bx1] x [by0, by1] that may hold a covered sample (inclusive: a film is at
    // most 65,536 pixels wide); bx0 > bx1 when the slot holds no triangle.
    uint16_t bx0 = 1, by0 = 0, bx1 = 0, by1 = 0;
    uint32_t material : 30 = 0;
    uint32_t front : 1 = 1;  // the camera sees the front side (front_facing); v is then reversed
    uint32_t small : 1 = 0;  // fits rasterize_small: at most kSmall pixels on each side
    float inv_area = 0.0f;   // 1 / twice the fixed-point area

    int x0() const { return bx0; }
    int x1() const { return bx1 + 1; }
    int y0() const { return by0; }
    int y1() const { return by1 + 1; }
    bool empty() const { return bx0 > bx1; }
    void make_empty() {
        bx0 = 1;
        bx1 = 0;
    }
};
static_assert(sizeof(SetupTriangle) == 64);

}  // namespace svetlo::raster

namespace svetlo {

struct PassMemory::Buffers {
    LargeArray<ClipVertex> vertices;
    LargeArray<raster::ScreenVertex> screen;
    LargeArray<raster::SetupTriangle> tris;
    LargeArray<raster::DepthTriangle> depth_tris;
};

}  // namespace svetlo

namespace svetlo::raster {

/// What the shading stages read (the vertex stage's lighting, flat faces, the fragments),
/// made once per frame by tessellate_scene and prepare_shading (raster_engine.cpp): the
/// materials as BSDFs and textures, and the lights. A pass without colour (depth, stencil)
/// leaves it empty, with mode Depth.
struct FrameShading {
    const Scene* scene = nullptr;
    Mode mode = Mode::Depth;
    std::vector<Material> materials;    // the light set's: the scene's, then the area lights'
    std::vector<Bsdf> constant_bsdf;    // per material, when it has no texture
    std::vector<char> textured;         // per material: some colour depends on uv
    std::vector<char> needs_footprint;  // per material: some texture is trilinear
    const std::vector<MipChain>* mips = nullptr;  // per texture, when some material needs them
    // Flat and Gouraud shading modulate their light by the base colour's texture per sample, as
    // OpenGL's GL_MODULATE: per material, that texture (null: none), and the material with it
    // made white, which the vertices and faces are lit with.
    std::vector<const ColorSource*> modulate;
    std::vector<Material> lit_white;
    std::optional<RasterLights> lights;  // made by tessellate_scene
    int light0_source = -1;              // the light set's index of Scene::lights[0]
    // Flat and Gouraud shading under a shadow technique light each face or vertex once per
    // light, so that each light's term can be multiplied by its mask per sample (as OpenGL's
    // one additive pass per light): the vertex colours and face colours then hold emission and
    // ambient only, and PassGeometry::vertex_light and face_light each light's term, `sources`
    // per vertex or triangle of the list.
    bool per_light = false;
    size_t sources = 0;
    const TriangleList* list = nullptr;  // the list the colour pass draws
    // The scene's instances when the frame draws them in place (placed_draws.h; null: as
    // copies in the scene's list). `list` is then the triangles the camera sees, and the
    // shadow techniques draw and trace the scene's list and these.
    std::shared_ptr<const PlacedDraws> placed;
};

/// What the SIMD fast path (fast_shading.cpp) reads besides FrameShading: the same lights and
/// materials in its own layout, and whether it takes them (constant Lambert and Phong-family
/// materials under point, spot and directional lights and VPLs). Made by prepare_fast_path
/// (raster_engine.cpp); the general shading (fragment.cpp) never reads it.
struct FastShading {
    // Per material, the sources of its ambient, diffuse and specular colours (colour_sources),
    // or none where `known` is false: the fast path evaluates a run's at once.
    struct ColourSources {
        const ColorSource* of[3] = {};
        bool known = false;
    };
    std::vector<ColourSources> colour_sources;
    SimdLights lights;                    // the frame's lights,
    bool lights_ok = false;               // when the fast path takes them all
    std::vector<SimdMaterial> materials;  // per material, and whether the fast path takes it
    std::vector<char> material_ok;
};

/// What a frame borrows from its caller to reuse between renders (the viewer's frames, the
/// compare command's techniques): the key of the frame's triangle list in those caches and
/// the caches of the ray-traced shadows (RenderOptions::accels, occluder_cubes).
struct FrameCaches {
    std::string list_key;  // empty: none (a scene made in code)
    AccelCache* accels = nullptr;
    OccluderCubeCache* occluder_cubes = nullptr;
};

/// What the geometry stages make of one pass (stages 2 to 4: draw_pass.cpp, vertex_stage.cpp,
/// setup_binning.cpp) and the rasterizer reads (stage 5): the camera, the transformed and
/// projected vertices, the set-up triangles and their bins.
struct PassGeometry {
    CameraMatrices cam;
    CullMode cull = CullMode::None;
    // Stages 2 to 4.
    LargeArray<ClipVertex> vertices;       // the vertex stage's output, one per list vertex
    LargeArray<ScreenVertex> screen;       // the same vertices projected (when inside)
    std::vector<ClipVertex> extra;         // vertices made by clipping (index bit kExtra)
    LargeArray<SetupTriangle> tris;        // one slot per input triangle (empty when culled)
    std::vector<SetupTriangle> clipped;    // triangles of clipped polygons, after the slots
    LargeArray<Color> flat;                // flat shading: each slot's face colour
    std::vector<Color> clipped_flat;       // and each clipped triangle's
    std::vector<uint32_t> clipped_source;  // the input triangle each clipped one comes from
    std::vector<std::pair<uint32_t, uint32_t>> clipped_range;  // per chunk, into `clipped`
    size_t triangle_count = 0;                                 // set up and drawn
    // Each light's term apart (FrameShading::per_light).
    std::vector<Color> vertex_light;  // Gouraud: per list vertex
    LargeArray<Color> face_light;     // flat: per list triangle
    // A depth-only pass (one sample per pixel at sample_bounds.lo, depth tested and written,
    // nothing else kept, as a shadow map's): with AVX2, its small, unclipped triangles are set
    // up eight at a time as DepthTriangles instead, chunk c's from depth_tris[c kChunk] on,
    // binned in depth_bins (their slots in `tris` are left as they were); the others, and
    // every triangle without AVX2, take the general road. The depth kept is the least of the
    // samples', so the order in which the two kinds are drawn does not matter.
    bool depth_only = false;
    LargeArray<DepthTriangle> depth_tris;
    // Whether the stages take their AVX2 forms (the *_avx2.cpp files were built and the
    // processor has AVX2: avx2_available()), decided once per pass by `assemble`.
    bool avx2 = false;
    /// Whether this pass makes and draws DepthTriangles.
    bool depth_records() const { return depth_only && avx2; }
    struct SampleBounds {
        glm::ivec2 lo{0}, hi{kSubpixel - 1};  // the samples' offsets in their pixel, fixed point
        int margin = 1;                       // pixels added on each side of a triangle's bounds
    } sample_bounds;
    struct Bins {                     // per chunk of triangles in drawing order:
        std::vector<uint32_t> start;  // tile k's triangles are ids[start[k] .. start[k+1])
        std::vector<uint32_t> ids;
    };
    std::vector<Bins> bins;
    std::vector<Bins> depth_bins;  // ids into depth_tris (a depth-only pass)
    int tiles_x = 0, tiles_y = 0;

    const ClipVertex& vertex(uint32_t v) const {
        return (v & kExtra) ? extra[v & ~kExtra] : vertices[v];
    }
    const SetupTriangle& tri(uint32_t id) const {
        return id < tris.size() ? tris[id] : clipped[id - tris.size()];
    }
    /// The input triangle of the draw list that set-up triangle `id` comes from.
    uint32_t source(uint32_t id) const {
        return id < tris.size() ? id : clipped_source[id - tris.size()];
    }
    Color flat_color(uint32_t id) const {
        return id < tris.size() ? flat[id] : clipped_flat[id - tris.size()];
    }
};

/// Everything the stages of a frame read: the shading, made once per frame, and the pass's
/// geometry, as the lecture's pipeline has them; then what the fast path and the caches add.
/// Each stage is given the part it reads (FrameShading, PassGeometry) where it reads one only.
struct FrameState : FrameShading, PassGeometry {
    FastShading fast;
    FrameCaches caches;
};

/// A face normal made unit, or +z for a face of no area.
inline vec3 unit_or_z(vec3 n) {
    return glm::length(n) > 0.0f ? glm::normalize(n) : vec3(0.0f, 0.0f, 1.0f);
}

/// A normal of the counter-clockwise side of a set-up triangle (world space, twice the area
/// long), from its vertices A, B, C in the wound order (reversed for front faces: the sign
/// undoes it exactly).
inline vec3 face_cross(const SetupTriangle& t, const ClipVertex& A, const ClipVertex& B,
                       const ClipVertex& C) {
    vec3 n = glm::cross(B.world - A.world, C.world - A.world);
    return t.front ? -n : n;
}

/// The same, of unit length ((0, 0, 1) for a triangle of no area).
inline vec3 face_normal(const SetupTriangle& t, const ClipVertex& A, const ClipVertex& B,
                        const ClipVertex& C) {
    return unit_or_z(face_cross(t, A, B, C));
}

/// A tile's sample buffers, reused from tile to tile. Each 8 x 8 block of pixels keeps the
/// farthest depth it holds (and, in passes that write no depth, the nearest): a coarse
/// hierarchical z-buffer, so that a triangle nearer nowhere than that is skipped for the block.
struct TileBuffers {
    static constexpr int kBlock = 8;
    static constexpr size_t kPad = 4;  // samples past the end, for four-wide loads and stores
    std::vector<float> depth;
    std::vector<uint32_t> tri;
    std::vector<uint8_t> stencil;   // per sample (and kPad), when a pass uses it
    std::vector<float> l1, l2;      // screen barycentrics of vertices 1 and 2 per sample,
                                    // written by rasterize_small (one sample per pixel)
    std::vector<float> block_far;   // per block: max depth over its samples
    std::vector<float> block_near;  // per block: min depth over its samples, when a pass
                                    // that writes no depth keeps it (else empty; block_far
                                    // is then exact too)
    float tile_near = 0.0f, tile_far = 0.0f;  // with block_near: min and max over the tile
    std::vector<Color> color;                 // resolved colour per pixel, accumulated over passes
    std::vector<Color> sample_color;          // the fast path's colour per sample
    std::vector<AovSum> aov;                  // per pixel, when AOVs are asked for
    // The visibility of each light of the light set at each sample (a shadow technique's
    // masks, row by row: light_visibility()); empty: every light visible.
    std::vector<float> visibility;
    uint64_t nonfinite = 0;  // samples dropped (black) for a colour that was not finite
    void reset(size_t samples, size_t pixels, bool aovs, bool stencil_used) {
        depth.assign(samples + kPad, kInfinity);
        tri.assign(samples + kPad, kNone);
        if (stencil_used) stencil.assign(samples + kPad, 0);
        if (l1.size() != samples + kPad) {
            l1.resize(samples + kPad);
            l2.resize(samples + kPad);
        }
        block_far.assign(static_cast<size_t>(kTile / kBlock) * (kTile / kBlock), kInfinity);
        if (color.size() != pixels) color.resize(pixels);
        if (aovs) aov.resize(pixels);
    }
};

struct SamplePattern {
    int count = 1;
    int32_t ox[kMaxSamplesPerPass], oy[kMaxSamplesPerPass];  // fixed-point offsets in the pixel
    vec2 offset[kMaxSamplesPerPass];
};

/// Samples [first, first + count) of a frame's stratified, jittered pattern of spp samples
/// per pixel: the same in every pixel, fixed by the seed (the pixel centre when spp is 1).
SamplePattern sample_pattern(int spp, uint64_t seed, int first, int count);

/// The triangle's edges, in the order of the barycentric weights of vertices 0, 1, 2.
struct TriangleEdges {
    Edge e[3];
    double inv_area = 0.0;
    TriangleEdges() = default;  // (no triangle: every weight 0)
    explicit TriangleEdges(const SetupTriangle& t)
        : e{Edge::make(t.x[1], t.y[1], t.x[2], t.y[2]), Edge::make(t.x[2], t.y[2], t.x[0], t.y[0]),
            Edge::make(t.x[0], t.y[0], t.x[1], t.y[1])},
          inv_area(t.inv_area) {}
    /// Screen-space barycentrics of vertices 1 and 2 at fixed-point (x, y).
    vec2 weights(int64_t x, int64_t y) const {
        return vec2(static_cast<float>(static_cast<double>(e[1].at(x, y)) * inv_area),
                    static_cast<float>(static_cast<double>(e[2].at(x, y)) * inv_area));
    }
    /// weights() at the n samples (x + k kSubpixel, y), k < n, into l1[k] and l2[k]: lane by
    /// lane where it can (the edge functions stepped in exact integers, computed as doubles,
    /// exact below 2^52), else one by one; the same numbers either way.
    void run_weights(int64_t x, int64_t y, int n, float* l1, float* l2) const {
        const int64_t at1 = e[1].at(x, y), at2 = e[2].at(x, y);
        const int64_t step1 = e[1].a * kSubpixel, step2 = e[2].a * kSubpixel;
        constexpr int64_t kExact = int64_t{1} << 52;
        if (n > 0 && (std::abs(at1) >= kExact || std::abs(at2) >= kExact ||
                      std::abs(step1) >= kExact / n || std::abs(step2) >= kExact / n)) {
            for (int k = 0; k < n; ++k) {
                const vec2 l = weights(x + static_cast<int64_t>(k) * kSubpixel, y);
                l1[k] = l.x;
                l2[k] = l.y;
            }
            return;
        }
        for (int k = 0; k < n; ++k) {  // (an int converts to double in SIMD; a size_t not)
            const auto j = static_cast<double>(k);
            l1[k] = static_cast<float>((static_cast<double>(at1) + j * static_cast<double>(step1)) *
                                       inv_area);
            l2[k] = static_cast<float>((static_cast<double>(at2) + j * static_cast<double>(step2)) *
                                       inv_area);
        }
    }
    /// The depth plane per pixel: z = z0 + dzdx (x - x0) + dzdy (y - y0), (x0, y0) vertex 0,
    /// from the gradients of the weights of vertices 1 and 2.
    void depth_gradient(const SetupTriangle& t, double& dzdx, double& dzdy) const {
        double per_pixel = static_cast<double>(kSubpixel) * inv_area;
        double z1 = t.z[1] - t.z[0], z2 = t.z[2] - t.z[0];
        dzdx = (static_cast<double>(e[1].a) * z1 + static_cast<double>(e[2].a) * z2) * per_pixel;
        dzdy = (static_cast<double>(e[1].b) * z1 + static_cast<double>(e[2].b) * z2) * per_pixel;
    }
};

/// Edge k of `te` for a stencil count from the sample (sx, sy) (fixed point): its value plus
/// its fill-rule bias there, and its changes one pixel right and one pixel down. An edge left
/// out of `crossing` (it holds the counted block whole) is zero, stepped by zero: inside
/// everywhere. Shared by the count's forms (stencil_count.cpp,
/// stencil_count_avx2.cpp).
struct CountEdge {
    int64_t value = 0, right = 0, down = 0;
};
inline CountEdge count_edge(const TriangleEdges& te, int k, int64_t sx, int64_t sy,
                            unsigned crossing) {
    if (((crossing >> k) & 1u) == 0) return {};
    const Edge& e = te.e[k];
    return {e.at(sx, sy) + e.bias, e.a * kSubpixel, e.b * kSubpixel};
}

/// The pixels of a tile a triangle's bounds cover: [xs, xe) x [ys, ye).
struct PixelSpan {
    int xs, xe, ys, ye;
    bool empty() const { return xs >= xe || ys >= ye; }
};

/// A shadow volume's stencil count over a rectangle of one tile's pixels (one sample per pixel,
/// the stencil test Always, no depth or item written; stencil_count.cpp): what every rectangle
/// of one triangle shares.
struct StencilCount {
    const SetupTriangle& t;
    const TriangleEdges& te;
    double dzdx, dzdy;  // the depth plane's gradient, per pixel
    const Tile& tile;
    const SamplePattern& sp;
    float depth_bias;
    int delta_pass, delta_fail;  // the count's change where the depth test passes, fails
};

/// A stencil count's change per operation: Keep, IncrWrap and DecrWrap only (else 2).
inline int stencil_delta(StencilOp op) {
    return op == StencilOp::Keep       ? 0
           : op == StencilOp::IncrWrap ? 1
           : op == StencilOp::DecrWrap ? -1
                                       : 2;
}

/// The count over the pixels r, adding delta_pass or delta_fail at every covered pixel
/// (wrapping), `crossing` the edges that cross r (the others hold it whole), `reach` the
/// largest |edge function| its steps can meet (32-bit lanes below 2^30), `all_fail` where every
/// sample fails the depth test; with AVX2 where `avx2`.
void count_stencil(const StencilCount& c, PixelSpan r, unsigned crossing, int64_t reach,
                   bool all_fail, bool avx2, TileBuffers& buf);

/// The pixels of the tile that triangle t may cover.
inline PixelSpan span_in(const SetupTriangle& t, const Tile& tile) {
    return {std::max(t.x0(), tile.x0), std::min(t.x1(), tile.x1), std::max(t.y0(), tile.y0),
            std::min(t.y1(), tile.y1)};
}

/// The tile's light visibility for the shading (simd_shading.h), `samples` samples a row.
inline LightVisibility light_visibility(const TileBuffers& buf, size_t samples) {
    return buf.visibility.empty() ? LightVisibility{}
                                  : LightVisibility{buf.visibility.data(), samples};
}

/// The fixed-point position of sample s of pixel `pixel` (row-major in the tile).
inline int64_t sample_x(const Tile& tile, size_t pixel, const SamplePattern& sp, int s) {
    auto tw = static_cast<size_t>(tile.x1 - tile.x0);
    return static_cast<int64_t>(tile.x0 + static_cast<int>(pixel % tw)) * kSubpixel + sp.ox[s];
}
inline int64_t sample_y(const Tile& tile, size_t pixel, const SamplePattern& sp, int s) {
    auto tw = static_cast<size_t>(tile.x1 - tile.x0);
    return static_cast<int64_t>(tile.y0 + static_cast<int>(pixel / tw)) * kSubpixel + sp.oy[s];
}

/// The edges of the last triangle asked for: neighbouring samples mostly share a triangle.
class EdgeCache {
public:
    explicit EdgeCache(const PassGeometry& f) : f_(f) {}
    const TriangleEdges& of(uint32_t id) {
        if (id != id_) {
            edges_ = TriangleEdges(f_.tri(id));
            id_ = id;
        }
        return edges_;
    }

private:
    const PassGeometry& f_;
    uint32_t id_ = kNone;
    TriangleEdges edges_;
};

/// The unit direction from world point p toward the camera.
inline vec3 view_direction(const PassGeometry& f, vec3 p) {
    return f.cam.orthographic ? -f.cam.forward : glm::normalize(f.cam.eye - p);
}

/// The guard band in clip space: |x| <= guard_x w, |y| <= guard_y w.
inline float guard_x(const PassGeometry& f) {
    return 1.0f + 2.0f * kGuardPixels / static_cast<float>(f.cam.width);
}
inline float guard_y(const PassGeometry& f) {
    return 1.0f + 2.0f * kGuardPixels / static_cast<float>(f.cam.height);
}

/// Stage 2 for positions: perspective division, viewport and snapping of a vertex inside the
/// near plane (w > 0).
ScreenVertex project(const PassGeometry& f, const ClipVertex& cv);
/// Stages 2 to 4 of a draw (draw_pass.cpp): the camera and the state into f, then the vertex
/// stage, clipping, setup and binning.
void prepare_pass(const TriangleList& list, const CameraMatrices& camera,
                  const PipelineState& state, FrameState& f, int threads);
/// draw_pass with the samples of `sp` (sp.count == targets.samples): a pass of the frame's
/// own sample pattern, such as the shadow techniques' depth and stencil passes.
void draw_samples(const TriangleList& list, const CameraMatrices& camera,
                  const PipelineState& state, RenderTargets& targets, int threads,
                  const SamplePattern& sp, PassMemory* memory = nullptr);
/// Bounds of triangles tight around the samples of `passes` (none but the wireframe's margin).
void fit_sample_bounds(PassGeometry& f, const std::vector<SamplePattern>& passes);

/// Stage 2 (vertex_stage.cpp): the vertex stage over every vertex of the list.
void vertex_stage(const TriangleList& list, FrameState& f, int threads);
/// Stages 3 and 4 (setup_binning.cpp): clipping, setup and binning in drawing order.
void assemble(const TriangleList& list, FrameState& f, int threads);
/// A depth-only pass's setup of `count` triangles of the list (`indices`, three each) eight at a
/// time, with AVX2 (depth_pass_avx2.cpp; only where avx2_available()): the small ones whose
/// vertices are all inside the clip volume become records out[0, n), n returned (with the
/// bounds, facing and culling of setup_triangle); those not inside, or not small, are listed
/// in others[other_count...] (offsets from the first, in order) for the caller; the rest draw
/// nothing. Only the first count - count % 8 are looked at.
size_t setup_depth_avx2(const PassGeometry& f, const uint32_t* indices, size_t count,
                        DepthTriangle* out, uint32_t* others, size_t& other_count);
/// A depth-only pass's records binned in the tile, with AVX2 (depth_pass_avx2.cpp; only where
/// avx2_available()): 4 x 2 pixels at a time, the same depths as rasterize_small.
void rasterize_depth_avx2(const PassGeometry& f, const Tile& tile, TileBuffers& buf);
/// count_stencil's count over the pixels r of a tile (its edge functions in 64-bit lanes where
/// `wide`, else 32-bit ones) with AVX2, 4 x 2 pixels at a time (stencil_count_avx2.cpp; only
/// where avx2_available()): the same counts.
void count_block_avx2(const StencilCount& c, PixelSpan r, unsigned crossing, bool all_fail,
                      bool wide, TileBuffers& buf);
/// Stage 4 for the painter's algorithm: binned again, back to front.
void bin_back_to_front(PassGeometry& f, int threads);
/// Calls draw(id, record(id)) for every id of `bins` binned in tile `ti`, in drawing order.
template <class Record, class Draw>
void for_each_in_bins(const std::vector<PassGeometry::Bins>& bins, size_t ti, Record&& record,
                      Draw&& draw) {
    for (const PassGeometry::Bins& b : bins) {
        const uint32_t end = b.start[ti + 1];
        for (uint32_t k = b.start[ti]; k < end; ++k) {
            // The triangles of a tile are scattered over the frame's: fetch ahead.
            constexpr uint32_t kAhead = 8;
            if (k + kAhead < end) __builtin_prefetch(&record(b.ids[k + kAhead]));
            draw(b.ids[k], record(b.ids[k]));
        }
    }
}
/// Calls draw(id, triangle) for every triangle binned in the tile, in drawing order.
template <class Draw>
void for_each_binned(const PassGeometry& f, const Tile& tile, Draw&& draw) {
    const size_t ti = static_cast<size_t>(tile.y0 / kTile) * f.tiles_x + tile.x0 / kTile;
    for_each_in_bins(
        f.bins, ti, [&](uint32_t id) -> const SetupTriangle& { return f.tri(id); }, draw);
}
/// Stage 5 (rasterize.cpp): every triangle binned in the tile, in order, into its buffers.
/// Passes with the stencil on or depth writes off take rasterize_tile_stencil.
void rasterize_tile(const PassGeometry& f, const Tile& tile, const SamplePattern& sp,
                    const PipelineState& state, TileBuffers& buf);
/// rasterize_tile for a pass with the stencil on or depth writes off (rasterize_stencil.cpp).
void rasterize_tile_stencil(const PassGeometry& f, const Tile& tile, const SamplePattern& sp,
                            const PipelineState& state, TileBuffers& buf);
/// Whether the sample at fixed-point (sx, sy) of triangle `id` (`t`, its edges `te`) falls in
/// a hole of its material's alpha (alpha_test.h): its perspective-correct texture coordinates,
/// and the pixel, sample and triangle (its item number) as a blend's coin (rasterize.cpp).
bool in_alpha_hole(const PassGeometry& f, uint32_t id, const SetupTriangle& t,
                   const TriangleEdges& te, int64_t sx, int64_t sy, const PipelineState& state);

}  // namespace svetlo::raster
