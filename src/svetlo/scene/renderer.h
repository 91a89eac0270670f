// The interface every engine implements, and what a render returns. Engines are an open set:
// src/svetlo/job/engines.cpp maps names to factories.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/scene/pixel_trace.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// The auxiliary buffers (docs/cli.md: --aov NAME=FILE).
inline const std::vector<std::string>& aov_names() {
    static const std::vector<std::string> names = {"depth", "normal", "albedo", "visibility"};
    return names;
}

/// The teaching buffers (docs/trace.md: debug AOVs), each made by some engines under some settings:
/// the rasterizer's light 0 shadow map (a cube map unfolded), shadow-volume stencil count and
/// projected planar shadow mask (docs/shadows.md); radiosity's patch mesh with each element's
/// value (docs/radiosity.md); the ray tracers' BVH cost of the camera ray (nodes, primitives,
/// their sum) and the path tracer's mean bounces per path (docs/trace.md).
struct DebugAov {
    std::string name;
    std::optional<ShadowTechnique> shadows;  // the technique it shows, where it shows one
};
inline const std::vector<DebugAov>& debug_aovs() {
    static const std::vector<DebugAov> table = {
        {"shadow_map", ShadowTechnique::Map}, {"stencil", ShadowTechnique::Volume},
        {"planar", ShadowTechnique::Planar},  {"patches", std::nullopt},
        {"bvh_cost", std::nullopt},           {"path_depth", std::nullopt},
    };
    return table;
}
inline std::vector<std::string> debug_aov_names() {
    std::vector<std::string> names;
    for (const DebugAov& d : debug_aovs()) names.push_back(d.name);
    return names;
}
/// The shadow technique debug AOV `name` shows (render.shadows must be it), if any.
inline std::optional<ShadowTechnique> debug_aov_technique(const std::string& name) {
    for (const DebugAov& d : debug_aovs())
        if (d.name == name) return d.shadows;
    return std::nullopt;
}

/// What an engine is and can do. The command line's checks and their messages are made from
/// it (src/svetlo/job/engines.h), not from engines' names.
struct Capabilities {
    std::string name;                     // its render.engine
    bool progressive = false;             // refines pass by pass: --time
    bool shows_passes = false;            // hands RenderOptions::on_pass its image as it refines
                                          // (the viewer streams them: /api/progressive)
    bool checkpoints = false;             // resumes from --checkpoint (RenderOptions::checkpoint)
    bool whole_frame = false;             // draws the whole frame at once: under MPI its
                                          // windows are bands of rows, each cut from a frame
    bool traces_samples = false;          // svetlo trace follows one sample of a pixel (--sample);
                                          // else its trace is of the whole pixel
    bool patch_mesh = false;              // solves on a mesh of patches (svetlo info shows it)
    std::vector<std::string> debug_aovs;  // the teaching buffers it makes
    int film_bytes_per_pixel = 16;        // its memory per film pixel, before AOVs (measured
                                          // as the peak's growth with the film: docs/web.md)
};

/// A window of the film: the pixels x0 <= i < x1, y0 <= j < y1 (docs/cli.md: --crop). A render
/// with one returns images of the window's size whose pixels are bit for bit those of the
/// full render at the same place.
struct Crop {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool operator==(const Crop&) const = default;
    /// The whole of a width x height film.
    static Crop full(int width, int height) { return {0, width, 0, height}; }
    /// Not empty, and inside a width x height film.
    bool inside(int width, int height) const {
        return x0 >= 0 && y0 >= 0 && x0 < x1 && y0 < y1 && x1 <= width && y1 <= height;
    }
};

struct RenderResult;
class AccelCache;         // geometry/accel_cache.h
class TriangleListCache;  // geometry/triangle_list_cache.h
class OccluderCubeCache;  // geometry/occluder_cube.h
class ProcessGroup;       // core/process_group.h

/// Many windows with one setup (docs/distributed.md): the engine renders the windows that
/// `next` hands out, one after the other, after one setup (the BVH, the radiosity solve), and
/// gives each window's result to `done`. A window's pixels are bit for bit those of the full
/// render, as a crop's.
struct WindowSource {
    std::function<bool(Crop& window)> next;  // false: no window left
    std::function<void(const Crop& window, RenderResult&& result)> done;
};

/// --checkpoint (docs/distributed.md): an engine's state, laid out as it chooses, restored
/// before its work and saved along it: the path tracer's accumulators after each pass, the
/// radiosity solve's light about once a second. `passes` counts what the state holds (passes,
/// or shots).
struct Checkpoint {
    /// Fills `state` (sized by the engine) from what was saved; returns the passes it holds (0:
    /// nothing saved, `state` untouched). Throws Error for a state of another size. An empty
    /// `state` takes what was saved whatever its size (the engine then checks it).
    std::function<int(std::vector<double>& state)> restore;
    std::function<void(int passes, const std::vector<double>& state)> save;
};

struct RenderOptions {
    int threads = 0;                      // 0 = all cores
    std::optional<Crop> crop;             // none: the whole film
    double time_budget = 0.0;             // seconds, 0 = none (--time; progressive engines)
    bool spp_caps_time = false;           // with a budget, stop at render.spp too (--spp given)
    bool progress = false;                // draw a progress bar on stderr
    std::vector<std::string> aovs;        // which of aov_names() to fill
    std::vector<std::string> debug_aovs;  // which of debug_aov_names() to make
    /// Set (by a signal) to stop a progressive engine after the pass in progress; the result
    /// holds the passes done. Engines of one pass finish it.
    const std::atomic<bool>* cancel = nullptr;
    /// Progressive engines call it after each pass with the passes done, the seconds since
    /// the setup and the image of those passes (--mse-log, compare --curves).
    std::function<void(int passes, double seconds, const Image& color)> on_pass;
    /// When set, the engine follows sample trace->sample of pixel (trace->x, trace->y) and
    /// records it there (svetlo trace); the crop should then be that pixel alone.
    PixelTrace* trace = nullptr;
    /// When set, the engine renders the windows it hands out instead of `crop`, and returns
    /// a result with no image and the stats of them all.
    WindowSource* windows = nullptr;
    /// When set, a progressive engine resumes from it and saves to it after every pass.
    const Checkpoint* checkpoint = nullptr;
    /// When set, the ray tracers take the scene's geometry and BVH from it, or build them
    /// into it: the renders of one command share one (svetlo compare, svetlo serve).
    AccelCache* accels = nullptr;
    /// When set, the rasterizer takes the scene's triangle list from it (and the BVH of its
    /// raytraced shadows from `accels`), or builds them into it.
    TriangleListCache* triangle_lists = nullptr;
    /// When set, the rasterizer's raytraced shadows keep the occluder cubes of their point
    /// casters in it (geometry/occluder_cube.h), for the next render with the same triangles
    /// and lights.
    OccluderCubeCache* occluder_cubes = nullptr;
    /// Under mpirun, the ranks that share this render (docs/distributed.md): an engine whose
    /// setup is worth splitting (the progressive radiosity solve) splits it among them.
    ProcessGroup* group = nullptr;
};

struct RenderStats {
    double seconds = 0.0;        // rendering, excluding scene setup
    double setup_seconds = 0.0;  // acceleration structure build and the like
    uint64_t rays = 0;           // all rays traced (camera, shadow, secondary)
    uint64_t triangles = 0;      // triangles set up for rasterization
    uint64_t nonfinite = 0;      // samples whose radiance was NaN or infinite: dropped (black)
    int passes = 0;              // progressive engines: passes (samples per pixel) done
    std::string detail;          // what else the engine reports in the summary line
};

struct RenderResult {
    Image color;  // linear radiance
    std::map<std::string, Image> aovs;
    RenderStats stats;
};

/// What the first hit of one camera sample gives the AOVs (the engines average it per pixel).
struct AovSample {
    float depth = 0.0f;       // distance from the camera
    vec3 normal{0.0f};        // world-space shading normal, toward the viewer
    Color albedo{0.0f};       // albedo_of the material
    float visibility = 1.0f;  // the fraction of light 0 that reaches the point
};

/// The auxiliary buffers, in the order of aov_names().
enum class Aov { Depth, Normal, Albedo, Visibility };
inline constexpr int kAovCount = 4;

/// One pixel's AOV samples added up, and their mean: the one accumulator of every engine
/// (double: the path tracer adds up a million passes).
struct AovSum {
    double depth = 0.0;
    glm::dvec3 normal{0.0}, albedo{0.0};
    double visibility = 0.0;

    /// Adds a sample with weight w (the rasterizer's MSAA weighs a shaded sample by the
    /// samples it covers).
    void add(const AovSample& s, double w = 1.0) {
        depth += w * s.depth;
        normal += w * glm::dvec3(s.normal);
        albedo += w * glm::dvec3(s.albedo);
        visibility += w * s.visibility;
    }
    void add(const AovSum& o) {
        depth += o.depth;
        normal += o.normal;
        albedo += o.albedo;
        visibility += o.visibility;
    }
    /// The mean of n samples.
    AovSample mean(double n) const {
        const double inv = 1.0 / n;
        return AovSample{static_cast<float>(depth * inv), vec3(normal * inv), Color(albedo * inv),
                         static_cast<float>(visibility * inv)};
    }
};
static_assert(sizeof(AovSum) == 8 * sizeof(double), "checkpoints store it as eight doubles");

/// The images a render fills: the colour, and the AOVs asked for (depth, normal and albedo
/// zero, visibility one).
struct AovTargets {
    Image* image[kAovCount] = {nullptr, nullptr, nullptr, nullptr};  // null: not asked for
    bool any = false;

    bool want(Aov a) const { return image[static_cast<int>(a)] != nullptr; }
    /// Writes one pixel's AOVs (a mean of its samples) into each image asked for.
    void write(int x, int y, const AovSample& s) const {
        if (Image* d = image[static_cast<int>(Aov::Depth)]) d->at(x, y) = Color(s.depth);
        if (Image* n = image[static_cast<int>(Aov::Normal)]) n->at(x, y) = s.normal;
        if (Image* a = image[static_cast<int>(Aov::Albedo)]) a->at(x, y) = s.albedo;
        if (Image* v = image[static_cast<int>(Aov::Visibility)]) v->at(x, y) = Color(s.visibility);
    }
};
inline AovTargets prepare_result(RenderResult& result, const std::vector<std::string>& aovs,
                                 int width, int height) {
    result.color = Image(width, height);
    AovTargets t;
    for (const std::string& name : aovs) {
        for (int k = 0; k < kAovCount; ++k) {
            if (name != aov_names()[static_cast<size_t>(k)]) continue;
            const bool visibility = k == static_cast<int>(Aov::Visibility);
            t.image[k] =
                &(result.aovs[name] = Image(width, height, Color(visibility ? 1.0f : 0.0f)));
        }
    }
    t.any = !result.aovs.empty();
    return t;
}

/// Whether the render is asked for AOV `a`.
inline bool wants_aov(const RenderOptions& options, Aov a) {
    const std::string& name = aov_names()[static_cast<size_t>(a)];
    for (const std::string& n : options.aovs)
        if (n == name) return true;
    return false;
}

/// Whether the render is asked for debug AOV `name`.
inline bool wants_debug_aov(const RenderOptions& options, const std::string& name) {
    for (const std::string& n : options.debug_aovs)
        if (n == name) return true;
    return false;
}

/// The engines' loop over what they render after their setup: `draw(window)` renders one
/// window. Without options.windows, the crop's window (or the whole film's), returned; with
/// them, each window handed out, given to windows->done, and the stats summed.
template <class Draw>
RenderResult render_windows(const Crop& single, const RenderOptions& options, Draw&& draw) {
    if (!options.windows) return draw(single);
    RenderResult total;
    Crop window;
    while (options.windows->next(window)) {
        RenderResult r = draw(window);
        total.stats.seconds += r.stats.seconds;
        total.stats.rays += r.stats.rays;
        total.stats.nonfinite += r.stats.nonfinite;
        total.stats.passes = r.stats.passes;
        total.stats.triangles = r.stats.triangles;
        total.stats.detail = r.stats.detail;
        options.windows->done(window, std::move(r));
    }
    return total;
}

/// The window a render covers: options.crop, or the whole film.
inline Crop film_window(const Scene& scene, const RenderOptions& options) {
    return options.crop ? *options.crop : Crop::full(scene.film.width, scene.film.height);
}

/// The window `window` of `frame`, a render of the whole width x height film: its images
/// that cover the film cut down to the window, the others (a shadow map) as they are.
inline RenderResult window_of(const RenderResult& frame, const Crop& window, int width,
                              int height) {
    auto cut = [&](const Image& image) {
        if (image.width != width || image.height != height) return image;
        return crop_image(image, window.x0, window.y0, window.width(), window.height());
    };
    RenderResult part;
    part.stats = frame.stats;
    part.color = cut(frame.color);
    for (const auto& [name, image] : frame.aovs) part.aovs[name] = cut(image);
    return part;
}

/// Cuts `result`, a render of the whole width x height film, down to `window` (engines that
/// draw the whole frame and keep the window: raster, radiosity's display).
inline void cut_to_window(RenderResult& result, const Crop& window, int width, int height) {
    if (window == Crop::full(width, height)) return;
    result = window_of(result, window, width, height);
}

class Renderer {
public:
    virtual ~Renderer() = default;
    virtual Capabilities capabilities() const = 0;
    virtual RenderResult render(const Scene& scene, const RenderOptions& options) = 0;
};

}  // namespace svetlo
