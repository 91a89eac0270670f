#include "svetlo/raster/raster_engine.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <unordered_map>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"
#include "svetlo/geometry/tessellate.h"
#include "svetlo/geometry/triangle_list_cache.h"
#include "svetlo/raster/fragment.h"
#include "svetlo/raster/pipeline.h"
#include "svetlo/raster/placed_draws.h"
#include "svetlo/raster/raster_trace.h"
#include "svetlo/raster/shadow_masks.h"
#include "svetlo/scene/instances.h"
#include "svetlo/scene/material_sources.h"

namespace svetlo {

using namespace raster;

namespace {

/// Whether a colour needs mip chains and the pixel footprint (trilinear or anisotropic).
bool uses_mips(const ColorSource& c) {
    return c.kind == ColorSource::Kind::Image &&
           (c.filter == TextureFilter::Trilinear || c.filter == TextureFilter::Anisotropic);
}

/// Gouraud shading lights each vertex once: a vertex shared by faces of different materials
/// is given one copy per material, as a GPU's vertex buffer would hold it.
void split_vertices_by_material(TriangleList& list) {
    std::vector<int64_t> material_of(list.positions.size(), -1);  // of the vertex's first face
    std::unordered_map<uint64_t, uint32_t> copies;                // (vertex, material) -> copy
    for (size_t t = 0; t < list.triangle_count(); ++t) {
        const uint32_t mat = list.material[t];
        for (int c = 0; c < 3; ++c) {
            uint32_t& v = list.indices[3 * t + c];
            if (material_of[v] < 0) material_of[v] = mat;
            if (material_of[v] == mat) continue;
            uint64_t key = (uint64_t{v} << 32) | mat;
            auto [it, made] = copies.try_emplace(key, static_cast<uint32_t>(list.positions.size()));
            if (made) {
                list.positions.push_back(list.positions[v]);
                list.normals.push_back(list.normals[v]);
                list.uvs.push_back(list.uvs[v]);
            }
            v = it->second;
        }
    }
}

/// Whether the frame draws the scene's instances in place (placed_draws.h) rather than as
/// copies in its list: every frame with instances but those whose passes need every triangle
/// in the one list: the overdraw count, the painter's algorithm and the wireframe (every
/// triangle's fragments or edges, hidden or not).
bool draws_in_place(const Scene& scene) {
    return !scene.instances.empty() && scene.render.shading != ShadingMode::Overdraw &&
           scene.render.raster.visibility != VisibilityMethod::Painter &&
           scene.render.raster.wireframe == WireframeMode::None;
}

/// The instances drawn in place of the last frame, and the key of its triangle list: a frame
/// of the same list (a drag in `svetlo serve`) takes them again instead of tessellating the
/// prototypes anew.
struct KeptPlacedDraws {
    std::string list_key;
    std::shared_ptr<const PlacedDraws> placed;
};

/// Stage 1: the scene-wide triangle list of every object, then the area lights as one-sided
/// emissive quads (the ray tracer shows them too), taken from `cache` when an earlier render of
/// the command made it (its key: `list_key`); and the instances drawn in place, taken from
/// `kept` when the last frame's list was the same. Makes the light set and its VPLs.
std::shared_ptr<const TriangleList> tessellate_scene(const Scene& scene, FrameShading& f,
                                                     std::string& list_key, int threads,
                                                     TriangleListCache* cache = nullptr,
                                                     IblCache* ibl = nullptr,
                                                     KeptPlacedDraws* kept = nullptr) {
    const TessellationOptions options = tessellation_options(scene.render);
    const bool in_place = draws_in_place(scene);
    // Refuse what would not fit in memory before making it (a fine tessellation of many shapes):
    // drawn in place, each prototype counts once.
    uint64_t total = tessellated_triangles(scene, options);
    if (in_place) {
        total -= sum_over_instances(
            scene, [&](const Object& o) { return tessellated_triangles(o, options); });
        std::vector<char> placed(scene.prototypes.size(), 0);
        for (const Instance& i : scene.instances) placed[i.prototype] = 1;
        for (size_t p = 0; p < scene.prototypes.size(); ++p)
            for (const Object& o : scene.prototypes[p].objects)
                total += placed[p] ? tessellated_triangles(o, options) : 0;
    }
    if (total > kMaxTriangles) {
        const std::string copies =
            !in_place && !scene.instances.empty()
                ? "; its instances are copies in the overdraw, painter and wireframe views, "
                  "placed in every other"
                : "";
        throw Error(scene.path.string(), "render.tessellation",
                    "the scene would make " + std::to_string(total) + " triangles (at most " +
                        std::to_string(kMaxTriangles) + "); lower render.tessellation" + copies);
    }
    f.lights.emplace(scene, threads, ibl);
    f.materials = f.lights->set.materials();
    const bool split = f.mode == Mode::Gouraud;
    const bool adjacency = scene.render.shadows == ShadowTechnique::Volume;  // silhouettes
    // The key names all the list is made of: the shapes, area lights and materials' order
    // (Scene::geometry_key; a scene made in code has none), the tessellation, and the steps
    // below.
    list_key.clear();
    if (!scene.geometry_key.empty()) {
        list_key = scene.geometry_key + " raster " + std::to_string(options.segments) +
                   (split ? " split" : "") + (adjacency ? " adjacency" : "") +
                   (in_place ? " in place" : "");
    }
    std::shared_ptr<const TriangleList> list =
        shared_entry<TriangleList>(cache, list_key, [&](TriangleList& made) {
            // Instances are drawn in place, or else as copies (scene/instances.h).
            const std::vector<Object> copies =
                in_place ? std::vector<Object>{} : instance_copies(scene);
            made = build_triangle_list(
                object_pointers(scene.objects, copies, f.lights->set.area_light_quads()), options,
                threads);
            if (split) split_vertices_by_material(made);
            if (adjacency) build_adjacency(made);
        });
    if (in_place && kept && !list_key.empty() && kept->list_key == list_key) {
        f.placed = kept->placed;
    } else if (in_place) {
        f.placed = std::make_shared<const PlacedDraws>(
            scene, options, static_cast<uint32_t>(list->triangle_count()), adjacency, threads);
        if (kept) *kept = {list_key, f.placed};
    }
    return list;
}

/// The base colour that flat and Gouraud shading modulate their light by (null: none). Not
/// an emissive material's albedo: its emission is not to be modulated.
template <class M>  // Material or const Material
auto* base_color(M& material) {
    using Source = std::conditional_t<std::is_const_v<M>, const ColorSource, ColorSource>;
    return std::visit(
        [](auto& mat) -> Source* {
            using T = std::decay_t<decltype(mat)>;
            if constexpr (std::is_same_v<T, LambertMaterial> ||
                          std::is_same_v<T, OrenNayarMaterial>) {
                return &mat.albedo;
            } else if constexpr (std::is_same_v<T, PhongMaterial>) {
                return &mat.kd;
            } else if constexpr (std::is_same_v<T, CookTorranceMaterial>) {
                return &mat.base_color;
            } else {
                return nullptr;
            }
        },
        material.model);
}

/// The mip chains of a frame's textures, kept from one frame to the next as a GL context keeps
/// a texture's levels: made again only when the textures' texels change (each frame of the
/// viewer loads the scene again, textures and all, and the chain of raster.json's floor took
/// half a millisecond of the frame's serial setup). Level 0 of each chain is the copy kept
/// here, for textures of at most kKeptBytes in all; larger ones (a copy would double their
/// memory) have their chains made every frame, level 0 the frame's own.
class KeptMipChains {
public:
    static constexpr size_t kKeptBytes = size_t{32} << 20;

    /// The chains of `textures`, made (when they must be) one texture per task on `threads`.
    const std::vector<MipChain>& of(const std::vector<TextureImage>& textures, int threads) {
        const bool same = kept_ && textures.size() == textures_.size() &&
                          std::equal(textures.begin(), textures.end(), textures_.begin(),
                                     [](const TextureImage& a, const TextureImage& b) {
                                         return a.same_texels(b);
                                     });
        if (same) return chains_;
        size_t bytes = 0;
        for (const TextureImage& t : textures) bytes += t.bytes();
        kept_ = bytes <= kKeptBytes;
        textures_ = kept_ ? textures : std::vector<TextureImage>{};
        const std::vector<TextureImage>& level0 = kept_ ? textures_ : textures;
        chains_.assign(level0.size(), MipChain{});
        parallel_indices(level0.size(), threads,
                         [&](size_t k) { chains_[k] = build_mip_chain(level0[k]); });
        return chains_;
    }

private:
    bool kept_ = false;  // textures_ holds the chains' level 0
    std::vector<TextureImage> textures_;
    std::vector<MipChain> chains_;
};

/// The shading state of the frame's colour pass: constant BRDFs made once, and mip chains
/// when a texture is filtered with them (`kept`'s).
void prepare_shading(const Scene& scene, FrameShading& f, KeptMipChains& kept, int threads) {
    // GL_MODULATE for flat and Gouraud shading: the base colour's texture, if any.
    for (const Material& m : f.materials) {
        const ColorSource* base = base_color(m);
        bool textured = base && base->varies();
        f.modulate.push_back(textured ? base : nullptr);
        Material white = m;
        if (ColorSource* white_base = base_color(white); textured && white_base)
            *white_base = ColorSource::constant(Color(1.0f));
        f.lit_white.push_back(std::move(white));
    }
    bool any_mips = false;
    for (const Material& m : f.materials) {
        f.textured.push_back(any_source(m, is_textured) ? 1 : 0);
        f.needs_footprint.push_back(any_source(m, uses_mips) ? 1 : 0);
        any_mips |= f.needs_footprint.back() != 0;
        f.constant_bsdf.push_back(make_bsdf(m, vec2(0.0f), scene.textures));
    }
    if (any_mips) f.mips = &kept.of(scene.textures, threads);
    const auto& sources = f.lights->set.sources();
    if (const LightSet::Source* s = f.lights->set.source_of_light(0))
        f.light0_source = static_cast<int>(s - sources.data());
}

/// The fast path's lights: point, spot and directional lights and the VPLs of lights with
/// area (lights_ok is false when the frame has another kind).
void prepare_fast_lights(const Scene& scene, const FrameShading& f, FastShading& fast) {
    fast.lights_ok = true;
    const auto& sources = f.lights->set.sources();
    for (uint32_t index = 0; index < sources.size(); ++index) {
        if (!sources[index].delta) {
            // The source's term is the mean of its n VPLs' (shading/direct_light.h).
            const auto& vpls = f.lights->vpls[index];
            for (const AreaPoint& a : vpls) {
                fast.lights.vpls.push_back(
                    {a.surface.p, a.surface.n,
                     a.radiance * (1.0f / (a.pdf_area * static_cast<float>(vpls.size()))),
                     f.lights->min_dist2[index], index});
            }
            continue;
        }
        const Light* light = &scene.lights[static_cast<size_t>(sources[index].light_index)];
        if (const auto* pl = std::get_if<PointLight>(light)) {
            fast.lights.points.push_back({pl->position, pl->intensity, index});
        } else if (const auto* dl = std::get_if<DirectionalLight>(light)) {
            fast.lights.directionals.push_back(
                {-glm::normalize(dl->direction), dl->irradiance, index});
        } else if (const auto* sl = std::get_if<SpotLight>(light)) {
            const float cos_inner = std::cos(radians(sl->inner_deg)),
                        cos_outer = std::cos(radians(sl->outer_deg));
            const float width = cos_inner - cos_outer;
            fast.lights.spots.push_back({sl->position, glm::normalize(sl->direction), sl->intensity,
                                         cos_outer, width > 0.0f ? 1.0f / width : 1e30f, index});
        } else {
            fast.lights_ok = false;
        }
    }
}

/// What the SIMD fast path takes of the frame (FastShading): constant Lambert and
/// Phong-family materials under point, spot and directional lights and VPLs.
void prepare_fast_path(const Scene& scene, const FrameShading& f, FastShading& fast) {
    prepare_fast_lights(scene, f, fast);
    for (size_t m = 0; m < f.materials.size(); ++m) {
        FastShading::ColourSources sources;
        sources.known = colour_sources(f.materials[m], sources.of);
        fast.colour_sources.push_back(sources);
        const Bsdf& b = f.constant_bsdf[m];
        bool phong = b.model == Bsdf::Model::Phong || b.model == Bsdf::Model::BlinnPhong;
        // Textured colours too: the fast path evaluates them per sample (material_at). Not an
        // emitting one: the fast path has no emission term.
        // Nor under an environment map: image-based lighting is shade_point's alone.
        // Nor a normal-mapped one: its normal is bent per sample in fragment.cpp. Nor one that
        // reads the second texture coordinate set or the vertex colour (surface_uvs's batches
        // carry set 0 only). Nor a shininess map (its batches take the shininess constant).
        const bool emits = !f.materials[m].emission.is_black();
        const auto* phong_material = std::get_if<PhongMaterial>(&f.materials[m].model);
        const bool shininess_mapped = phong_material && phong_material->shininess_map.varies();
        const bool ibl = f.lights->environment.active();
        const bool mapped = f.materials[m].has_normal_map();
        const bool varyings = any_source(f.materials[m], reads_more_than_uv);
        fast.material_ok.push_back((phong || b.model == Bsdf::Model::Lambert) && !emits && !ibl &&
                                           !mapped && !varyings && !shininess_mapped
                                       ? 1
                                       : 0);
        fast.materials.emplace_back(b.ambient, b.diffuse, b.specular, b.shininess,
                                    b.model == Bsdf::Model::BlinnPhong, phong);
    }
}

/// The pipeline state of the frame's colour pass.
PipelineState colour_pass_state(const Scene& scene) {
    PipelineState state;
    state.depth_test = scene.render.raster.visibility != VisibilityMethod::Painter;
    state.cull = scene.render.raster.cull_back_faces ? CullMode::Back : CullMode::None;
    if (scene.render.shading == ShadingMode::Overdraw) {
        // The stencil buffer counts every fragment, whether the depth test keeps it or not.
        state.stencil.enabled = true;
        state.stencil.front = {StencilFunc::Always, StencilOp::Keep, StencilOp::Incr,
                               StencilOp::Incr};
        state.stencil.back = state.stencil.front;
    }
    return state;
}

/// A lower bound on the distance of anything the camera sees (0: none): the distance from the
/// eye to the nearest plane of a triangle not wholly behind it. The near plane goes at half of
/// it (camera_matrices), so that nothing visible is clipped. Over chunks of the triangles on
/// `threads` threads (a frame's setup waits for it): the least of their minima, whichever
/// order they come in.
float nearest_depth(const TriangleList& list, const Camera& camera, int threads) {
    const vec3 eye = camera.position, forward = glm::normalize(camera.look_at - eye);
    const float nearest = parallel_min(
        list.triangle_count(), threads,
        [&](size_t begin, size_t end) {
            float chunk = kInfinity;
            for (size_t t = begin; t < end; ++t) {
                const vec3 a = list.positions[list.indices[3 * t]],
                           b = list.positions[list.indices[3 * t + 1]],
                           c = list.positions[list.indices[3 * t + 2]];
                chunk = std::min(chunk, nearest_plane(a, b, c, eye, forward));
            }
            return chunk;
        },
        8192);
    return std::isfinite(nearest) ? nearest : 0.0f;
}

}  // namespace

CameraMatrices frame_camera(const Scene& scene, const TriangleList& list, int threads,
                            const PlacedDraws* placed) {
    float nearest = nearest_depth(list, scene.camera, threads);
    if (placed) {
        const float of_placed = placed->nearest_depth(
            scene.camera.position, glm::normalize(scene.camera.look_at - scene.camera.position),
            threads);
        if (std::isfinite(of_placed) && (nearest == 0.0f || of_placed < nearest))
            nearest = of_placed;
    }
    return camera_matrices(scene.camera, scene.film.width, scene.film.height,
                           SceneTriangles{list, placed}.bounds(), nearest);
}

CameraMatrices raster_camera(const Scene& scene) {
    FrameState f;
    f.scene = &scene;
    const auto list = tessellate_scene(scene, f, f.caches.list_key, 0);
    return frame_camera(scene, *list, 0, f.placed.get());
}

struct RasterRenderer::Buffers {
    LargeArray<ClipVertex> vertices;
    LargeArray<ScreenVertex> screen;
    LargeArray<SetupTriangle> tris;
    LargeArray<Color> flat;
    PassMemory passes;  // the shadow techniques' passes
    KeptMipChains mips;
    IblCache ibl;
    KeptPlacedDraws placed;
};

RasterRenderer::RasterRenderer() : buffers_(std::make_unique<Buffers>()) {}
RasterRenderer::~RasterRenderer() = default;

namespace {

/// Refuses what the rasterizer cannot draw: a thin lens, and a debug AOV of a shadow technique
/// the scene does not use (the table in renderer.h).
void check_raster_request(const Scene& scene, const RenderOptions& options) {
    if (scene.camera.aperture > 0.0f) {
        throw Error(scene.path.string(), "camera.aperture",
                    "the rasterizer draws through a pinhole; a thin lens needs the whitted or "
                    "path engine");
    }
    for (const std::string& name : options.debug_aovs) {
        const std::optional<ShadowTechnique> technique = debug_aov_technique(name);
        if (technique && scene.render.shadows != *technique)
            throw Error(scene.path.string(), "render.shadows",
                        "the " + name + " AOV needs render.shadows " +
                            std::string(name_of(kShadowTechniques, *technique)));
    }
}

/// What every tile of one colour pass shares.
struct ColourPass {
    const FrameState& f;
    const std::vector<SamplePattern>& passes;  // the sample positions, pass by pass
    const PipelineState& state;
    ShadowTechniqueState* shadows;  // the technique's maps, volumes or masks (none: unlit)
    const AovTargets& targets;
    int spp;
    bool msaa;
    bool simd;                // the fast path (fast_shading.cpp) where it applies
    bool small_left_weights;  // rasterize_small keeps its samples' screen barycentrics
};

/// One tile of the frame, stage 5 on: for each sample pass its rasterization, the shadow
/// technique's masks, the shading of its visible samples; then the resolve into `color`.
void draw_tile(const ColourPass& c, const Tile& tile, TileBuffers& buf, MaskScratch& scratch,
               Image& color) {
    const size_t pixels = static_cast<size_t>(tile.x1 - tile.x0) * (tile.y1 - tile.y0);
    // (One sample per pixel on the fast path writes every pixel: nothing to clear.)
    if (!(c.simd && c.spp == 1)) buf.color.assign(pixels, Color(0.0f));
    if (c.targets.any) {
        buf.aov.assign(pixels, AovSum{});
    }
    for (size_t pass = 0; pass < c.passes.size(); ++pass) {
        const SamplePattern& sp = c.passes[pass];
        const int S = sp.count;
        buf.reset(pixels * static_cast<size_t>(S), pixels, c.targets.any, c.state.stencil.enabled);
        rasterize_tile(c.f, tile, sp, c.state, buf);
        if (c.shadows) {
            fill_masks(*c.shadows, c.f, tile, sp, static_cast<int>(pass), c.small_left_weights, buf,
                       scratch);
        }
        if (!c.simd) {
            shade_tile(c.f, tile, sp, c.msaa, c.targets.any, buf);
        } else {
#if SVETLO_SIMD
            shade_tile_fast(c.f, tile, sp, c.small_left_weights, buf);
#endif
            if (c.spp == 1) {  // nothing to add up: the samples are the pixels
                std::swap(buf.color, buf.sample_color);
            } else {
                accumulate_samples(buf, pixels, S, buf.color.data());
            }
        }
    }
    resolve_tile(c.f, tile, c.spp, c.passes.back().count, c.targets, buf, color);
}

/// The debug AOVs of the scene's shadow technique (checked by check_raster_request): light
/// 0's shadow map, projected mask or stencil count.
void debug_aov_images(const Scene& scene, const RenderOptions& options,
                      const ShadowTechniqueState* shadows, RenderResult& result) {
    for (const std::string& name : options.debug_aovs) {
        const ShadowTechnique technique = *debug_aov_technique(name);
        Image image = technique == ShadowTechnique::Map      ? shadows->shadow_map_image()
                      : technique == ShadowTechnique::Planar ? shadows->mask_image()
                                                             : shadows->stencil_image();
        if (image.width == 0)
            throw Error(scene.path.string(), "lights",
                        "the " + name + " AOV shows light 0's shadows, and it casts none");
        result.aovs[name] = std::move(image);
    }
}

}  // namespace

// A window costs the rasterizer its whole frame's setup anyway: the frame is drawn once.
RenderResult RasterRenderer::render_cut_into_windows(const Scene& scene,
                                                     const RenderOptions& options) {
    RenderOptions whole = options;
    whole.windows = nullptr;
    whole.crop.reset();
    const RenderResult frame = render(scene, whole);
    Crop window;
    while (options.windows->next(window))
        options.windows->done(window,
                              window_of(frame, window, scene.film.width, scene.film.height));
    RenderResult total;
    total.stats = frame.stats;
    return total;
}

std::shared_ptr<const TriangleList> RasterRenderer::begin_frame(const Scene& scene,
                                                                const RenderOptions& options,
                                                                FrameState& f) {
    f.vertices = std::move(buffers_->vertices);  // the last frame's memory, given back by end_frame
    f.screen = std::move(buffers_->screen);
    f.tris = std::move(buffers_->tris);
    f.flat = std::move(buffers_->flat);
    f.scene = &scene;
    f.mode = scene.render.shading;
    const std::shared_ptr<const TriangleList> shared_list =
        tessellate_scene(scene, f, f.caches.list_key, options.threads, options.triangle_lists,
                         &buffers_->ibl, &buffers_->placed);
    const TriangleList& list = *shared_list;
    f.caches.accels = options.accels;
    f.caches.occluder_cubes = options.occluder_cubes;
    prepare_shading(scene, f, buffers_->mips, options.threads);
    prepare_fast_path(scene, f, f.fast);
    f.list = &list;
    f.sources = f.lights->set.sources().size();
    // Each light's term apart, for its mask (flat and Gouraud shading under a shadow
    // technique); with no light there is no term to mask.
    f.per_light = scene.render.shadows != ShadowTechnique::None && f.sources > 0 &&
                  (f.mode == Mode::Flat || f.mode == Mode::Gouraud);
    return shared_list;
}

void RasterRenderer::end_frame(FrameState& f) {
    buffers_->vertices = std::move(f.vertices);
    buffers_->screen = std::move(f.screen);
    buffers_->tris = std::move(f.tris);
    buffers_->flat = std::move(f.flat);
}

RenderResult RasterRenderer::render(const Scene& scene, const RenderOptions& options) {
    check_raster_request(scene, options);
    if (options.trace) return trace_raster_pixel(*this, scene, options);
    if (options.windows) return render_cut_into_windows(scene, options);
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    const int width = scene.film.width, height = scene.film.height, spp = scene.render.spp;
    const int threads = options.threads;
    FrameState f;
    const std::shared_ptr<const TriangleList> shared_list = begin_frame(scene, options, f);
    const TriangleList& list = *shared_list;
    const CameraMatrices camera = frame_camera(scene, list, threads, f.placed.get());
    // The frame's sample positions, pass by pass (the same in every pixel).
    std::vector<SamplePattern> passes;
    for (int first = 0; first < spp; first += kMaxSamplesPerPass)
        passes.push_back(sample_pattern(spp, scene.render.seed, first,
                                        std::min(kMaxSamplesPerPass, spp - first)));
    if (scene.render.raster.wireframe == WireframeMode::None) fit_sample_bounds(f, passes);
    // The output images are allocated (and their pages touched) as part of the setup, as a
    // GPU's framebuffer exists before the frame.
    RenderResult result;
    // Looked up once: the tiles write through these concurrently.
    const AovTargets targets = prepare_result(result, options.aovs, width, height);

    // Setup ends here: what follows is the pipeline proper, the work of every frame. One
    // colour pass: stages 2 to 4 for the whole frame, then per tile the rasterization of each
    // sample pass, the shading of its visible samples, and the resolve.
    auto t1 = Clock::now();
    const AlphaTest alpha(f.materials, scene.textures);
    PipelineState state = colour_pass_state(scene);
    if (alpha.any()) state.alpha = &alpha;
    // Instances drawn in place: the colour pass draws the triangles a visibility pass of the
    // whole scene finds (placed_draws.h); the shadow techniques see the whole scene.
    VisibleTriangles visible;
    if (f.placed) {
        visible = visible_triangles(SceneTriangles{list, f.placed.get()}, camera, state, passes,
                                    f.mode == Mode::Gouraud, threads, &buffers_->passes);
        f.list = &visible.list;
        state.items = visible.items.data();  // (a blend's coins, as the visibility pass's)
    }
    prepare_pass(*f.list, camera, state, f, threads);
    if (!state.depth_test) bin_back_to_front(f, threads);  // the painter's algorithm
    // The shadow technique's maps, volumes or stencil masks, before the colour pass reads them
    // (for the lit modes, and for the visibility AOV).
    const bool lit_mode = f.mode == Mode::Phong || f.mode == Mode::Gouraud || f.mode == Mode::Flat;
    std::unique_ptr<ShadowTechniqueState> shadows;
    if (lit_mode || targets.want(Aov::Visibility) || !options.debug_aovs.empty())
        shadows = make_shadow_technique(scene, list, f, passes, threads, &buffers_->passes);

    const bool msaa = scene.render.raster.msaa;
    // The fast path (fast_shading.cpp, SSE or AVX2) where it applies; its twin, the general
    // shading (fragment.cpp), everywhere else and in a build without SIMD. Small triangles go
    // through rasterize_small, which keeps the screen barycentrics of the samples it writes,
    // unless the stencil is on.
    const ColourPass pass{
        f,
        passes,
        state,
        shadows.get(),
        targets,
        spp,
        msaa,
        SVETLO_SIMD && f.mode == Mode::Phong && !msaa && !targets.any && f.fast.lights_ok,
        !state.stencil.enabled};
    PerWorker<TileBuffers> buffers(threads);
    PerWorker<MaskScratch> mask_scratch(threads);
    Progress progress("raster", static_cast<int64_t>(width) * height, options.progress);
    parallel_tiles(
        width, height, kTile, threads,
        [&](const Tile& tile) {
            draw_tile(pass, tile, buffers.local(), mask_scratch.local(), result.color);
        },
        [&](int pixels) { progress.advance(pixels); });
    progress.finish();
    result.stats.setup_seconds = std::chrono::duration<double>(t1 - t0).count();
    result.stats.seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    result.stats.triangles = f.triangle_count;
    for (TileBuffers& buf : buffers) result.stats.nonfinite += buf.nonfinite;
    debug_aov_images(scene, options, shadows.get(), result);
    end_frame(f);
    // A crop: the frame is drawn whole (its cost is the frame's setup) and cut.
    cut_to_window(result, film_window(scene, options), width, height);
    return result;
}

}  // namespace svetlo
