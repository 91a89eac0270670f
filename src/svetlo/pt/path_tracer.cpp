#include "svetlo/pt/path_tracer.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"
#include "svetlo/geometry/avx2.h"
#include "svetlo/pt/guiding_field.h"
#include "svetlo/pt/path_integrator.h"
#include "svetlo/rt/camera.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {

namespace {

/// A render's images and accumulators may take at most this much memory.
constexpr double kMaxFilmBytes = 4.0 * (1ULL << 30);

/// The stream of pixel `pixel`'s sample in pass `pass`.
Rng sample_rng(uint64_t seed, int pass, uint64_t pixel) {
    return pixel_rng(mix64(mix64(seed) + static_cast<uint64_t>(pass)), pixel);
}

/// Per pixel, the sums of the passes (double: a million passes keep their precision).
struct FilmSums {
    std::vector<glm::dvec3> color;
    std::vector<AovSum> aov;        // when any AOV is asked for
    std::vector<glm::dvec4> debug;  // the bvh_cost (nodes, primitives, sum), then bounces

    /// Every sum as one array of doubles, in the order above (--checkpoint), and back.
    size_t doubles() const { return 3 * color.size() + 8 * aov.size() + 4 * debug.size(); }
    std::vector<double> flat() const {
        std::vector<double> out;
        out.reserve(doubles());
        for (const glm::dvec3& v : color) out.insert(out.end(), {v.x, v.y, v.z});
        for (const AovSum& a : aov) {
            out.insert(out.end(), {a.depth, a.normal.x, a.normal.y, a.normal.z, a.albedo.x,
                                   a.albedo.y, a.albedo.z, a.visibility});
        }
        for (const glm::dvec4& v : debug) out.insert(out.end(), {v.x, v.y, v.z, v.w});
        return out;
    }
    void load(const std::vector<double>& in) {
        size_t k = 0;
        for (glm::dvec3& v : color) {
            v = glm::dvec3(in[k], in[k + 1], in[k + 2]);
            k += 3;
        }
        for (AovSum& a : aov) {
            a.depth = in[k];
            a.normal = glm::dvec3(in[k + 1], in[k + 2], in[k + 3]);
            a.albedo = glm::dvec3(in[k + 4], in[k + 5], in[k + 6]);
            a.visibility = in[k + 7];
            k += 8;
        }
        for (glm::dvec4& v : debug) {
            v = glm::dvec4(in[k], in[k + 1], in[k + 2], in[k + 3]);
            k += 4;
        }
    }
    /// The sums of `window`'s pixels, these being a `width`-wide film's from its corner.
    FilmSums window_of(const Crop& window, int width) const {
        FilmSums out;
        for (int j = window.y0; j < window.y1; ++j) {
            const auto row = static_cast<ptrdiff_t>(j) * width;
            auto part = [&](const auto& from, auto& to) {
                if (from.empty()) return;
                to.insert(to.end(), from.begin() + row + window.x0, from.begin() + row + window.x1);
            };
            part(color, out.color);
            part(aov, out.aov);
            part(debug, out.debug);
        }
        return out;
    }
};

/// What every pass of one render shares: the scene made ready, and what is asked of it.
struct PassSetup {
    const Scene& scene;
    const RtScene& rt;
    const LightSelection& selection;
    const WavelengthWeights& wavelengths;
    const CausticPhotons* photons;
    const CameraRays& camera;
    const RenderOptions& options;
    bool want_cost, want_depth, want_visibility, want_aovs;
    bool avx2;  // the sampler's eight lanes: the same numbers

    /// Sums for `pixels` pixels, with what is asked for.
    FilmSums sums(size_t pixels) const {
        FilmSums s;
        s.color.assign(pixels, glm::dvec3(0.0));
        if (want_cost || want_depth) s.debug.assign(pixels, glm::dvec4(0.0));
        if (want_aovs) s.aov.assign(pixels, AovSum{});
        return s;
    }
};

/// Pass `pass` (one sample per pixel) over `window`, in the film's pixel coordinates, added
/// to `sums`, the window's. With a guiding field, its bounces are guided, and with `train`
/// recorded into it.
void trace_pass(const PassSetup& s, const Crop& window, int pass, GuidingField* guide, bool train,
                FilmSums& sums, std::atomic<uint64_t>& rays, std::atomic<uint64_t>& nonfinite,
                Progress& progress) {
    const Scene& scene = s.scene;
    const int width = scene.film.width, height = scene.film.height;
    const int ww = window.width(), wh = window.height();
    parallel_tiles(
        ww, wh, s.options.threads,
        [&](const Tile& tile) {
            PathIntegrator integrator(s.rt, s.selection, s.wavelengths, s.photons);
            integrator.guide(guide, train);
            uint64_t dropped = 0;
            for (int j = window.y0 + tile.y0; j < window.y0 + tile.y1; ++j) {
                for (int i = window.x0 + tile.x0; i < window.x0 + tile.x1; ++i) {
                    const size_t pixel = static_cast<size_t>(j) * width + i;
                    const size_t slot = static_cast<size_t>(j - window.y0) * ww + (i - window.x0);
                    SobolSampler sampler(scene.render.seed, pixel, static_cast<uint32_t>(pass),
                                         s.avx2);
                    // The visibility AOV's own stream, made only when it is asked for.
                    std::optional<Rng> aov_rng;
                    if (s.want_visibility)
                        aov_rng = sample_rng(scene.render.seed ^ 0xa0a0a0a0ULL, pass, pixel);
                    vec2 jitter = sampler.next_2d();
                    float x = (static_cast<float>(i) + jitter.x) / width;
                    float y = (static_cast<float>(j) + jitter.y) / height;
                    AovSample aov;
                    Ray ray = s.camera.thin_lens() ? s.camera.generate(x, y, sampler.next_2d())
                                                   : s.camera.generate(x, y);
                    if (s.want_cost)
                        sums.debug[slot] += glm::dvec4(glm::dvec3(s.rt.camera_ray_cost(ray)), 0.0);
                    PixelTrace* log = s.options.trace;
                    std::optional<PathTraceLog> traced;
                    if (log && log->at(i, j) && log->sample == pass) {
                        traced.emplace(*log, scene.material_names);
                        integrator.observer = &*traced;
                    }
                    Color c = integrator.radiance(ray, sampler, s.want_aovs ? &aov : nullptr,
                                                  aov_rng ? &*aov_rng : nullptr);
                    if (traced) record_total(*log, c, is_finite(c));
                    integrator.observer = nullptr;
                    if (s.want_depth) sums.debug[slot].w += integrator.bounces;
                    // A sample that is not finite never reaches the pixel: it counts as
                    // black, and is reported.
                    if (!is_finite(c)) {
                        ++dropped;
                        continue;
                    }
                    sums.color[slot] += glm::dvec3(c);
                    if (s.want_aovs && is_finite(aov.normal) && is_finite(aov.albedo))
                        sums.aov[slot].add(aov);
                }
            }
            rays += integrator.rays;
            nonfinite += dropped;
        },
        [&](int n) { progress.advance(n); });
}

/// The mean of `passes` passes' colour sums.
Image mean_color(const FilmSums& sums, int width, int height, int passes) {
    Image image(width, height);
    for (size_t slot = 0; slot < sums.color.size(); ++slot)
        image.pixels[slot] = Color(sums.color[slot] * (1.0 / passes));
    return image;
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Throws unless the images and the accumulators fit: for the crop, or the whole film when
/// windows are handed out, 12 bytes a pixel per image, 24 for the colour's sums and 64 for
/// the AOVs'; with guiding, the whole film's sums of the training passes too.
void check_film_memory(const Scene& scene, const RenderOptions& options) {
    const int width = scene.film.width, height = scene.film.height;
    const Crop largest = film_window(scene, options);
    const double images = 1.0 + static_cast<double>(options.aovs.size());
    const double sum_bytes = 24.0 + (options.aovs.empty() ? 0.0 : 64.0);
    double bytes =
        static_cast<double>(largest.width()) * largest.height() * (12.0 * images + sum_bytes) +
        (scene.render.guiding ? static_cast<double>(width) * height * sum_bytes : 0.0);
    if (bytes > kMaxFilmBytes) {
        throw Error(scene.path.string(), "film",
                    "the path tracer's film of " + std::to_string(width) + " x " +
                        std::to_string(height) + " pixels needs " +
                        std::to_string(static_cast<long long>(bytes / (1 << 20))) +
                        " MiB (at most 4096)");
    }
}

/// How many passes a render makes: the scene's spp, or as many as its time allows.
struct PassPlan {
    int max_passes;
    bool budget;  // --time: passes until it is spent
};

/// What path guiding's training leaves for the render's passes: the field, the whole film's
/// sums of the training passes (the start of every window's) and their count, time and rays.
struct Training {
    std::unique_ptr<GuidingField> guide;
    FilmSums sums;
    int passes = 0;
    double seconds = 0.0;
    std::atomic<uint64_t> rays{0}, nonfinite{0};
};

/// Path guiding's training (docs/path.md, "Path guiding"): the first passes, over the whole
/// film whatever the window, so that the field, and so every pixel, is the full render's.
void train_guide(const PassSetup& setup, CausticPhotons* photons, const Bounds3& bounds,
                 const PassPlan& plan, Training& t) {
    const Scene& scene = setup.scene;
    const RenderOptions& options = setup.options;
    const int width = scene.film.width, height = scene.film.height;
    const auto start = Clock::now();
    t.guide = std::make_unique<GuidingField>(bounds);
    const int training =
        std::min(guiding_training_passes(scene.render.spp, plan.budget && !options.spp_caps_time),
                 plan.max_passes);
    const Crop film = Crop::full(width, height);
    const Crop largest = film_window(scene, options);
    const size_t pixels = static_cast<size_t>(width) * height;
    if (training > 0) t.sums = setup.sums(pixels);
    Progress progress("path: guiding",
                      static_cast<int64_t>(training) * static_cast<int64_t>(pixels),
                      options.progress);
    if (plan.budget) progress.set_budget(options.time_budget);
    for (int pass = 0; pass < training; ++pass) {
        if (pass > 0 && plan.budget && seconds_since(start) >= options.time_budget) break;
        if (pass > 0 && options.cancel && options.cancel->load()) break;
        progress.set_status("training pass " + std::to_string(pass + 1) + "/" +
                            std::to_string(training));
        if (photons) photons->build(pass, options.threads);
        trace_pass(setup, film, pass, t.guide.get(), true, t.sums, t.rays, t.nonfinite, progress);
        ++t.passes;
        int iteration_passes = 0;
        if (ends_guiding_iteration(pass, iteration_passes)) t.guide->refine(iteration_passes);
        if (options.on_pass && !options.windows) {
            options.on_pass(t.passes, seconds_since(start),
                            mean_color(t.sums.window_of(largest, width), largest.width(),
                                       largest.height(), t.passes));
        }
    }
    progress.finish();
    t.seconds = seconds_since(start);
}

/// A window's images from its sums over `passes` passes: the colour, the AOVs asked for and
/// the debug AOVs (the camera rays' cost, the paths' bounces).
void resolve_window(const PassSetup& setup, const FilmSums& sums, int passes, int ww, int wh,
                    const AovTargets& targets, RenderResult& result) {
    const size_t pixels = static_cast<size_t>(ww) * static_cast<size_t>(wh);
    const double inv = 1.0 / passes;
    if (setup.want_cost || setup.want_depth) {
        Image cost(ww, wh), depth(ww, wh);
        for (size_t pixel = 0; pixel < pixels; ++pixel) {
            const glm::dvec4 d = sums.debug[pixel] * inv;
            cost.pixels[pixel] = Color(d.x, d.y, d.z);
            depth.pixels[pixel] = Color(static_cast<float>(d.w));
        }
        if (setup.want_cost) result.aovs["bvh_cost"] = std::move(cost);
        if (setup.want_depth) result.aovs["path_depth"] = std::move(depth);
    }
    for (size_t pixel = 0; pixel < pixels; ++pixel) {
        const int i = static_cast<int>(pixel % ww), j = static_cast<int>(pixel / ww);
        result.color.at(i, j) = Color(sums.color[pixel] * inv);
        if (targets.any) targets.write(i, j, sums.aov[pixel].mean(passes));
    }
}

/// The passes over one window (the crop, or one of options.windows), in the film's pixel
/// coordinates, after guiding's training: a pixel's samples depend only on its place and the
/// pass, so a window is the full render's. --checkpoint's saved passes are taken up first.
RenderResult render_window(const PassSetup& setup, CausticPhotons* photons,
                           const Training& training, const PassPlan& plan, const Crop& window) {
    const RenderOptions& options = setup.options;
    const int width = setup.scene.film.width;
    const auto start = Clock::now();
    const int ww = window.width(), wh = window.height();
    const size_t pixels = static_cast<size_t>(ww) * static_cast<size_t>(wh);
    RenderResult result;
    const AovTargets targets = prepare_result(result, options.aovs, ww, wh);
    FilmSums sums =
        training.passes > 0 ? training.sums.window_of(window, width) : setup.sums(pixels);
    std::atomic<uint64_t> rays{0}, nonfinite{0};

    // --checkpoint: the passes already saved, and their sums (guiding's training is traced
    // again: the field is not saved, and its passes come out the same).
    int passes = training.passes;
    if (options.checkpoint) {
        std::vector<double> state(sums.doubles());
        const int saved = options.checkpoint->restore(state);
        if (saved > passes) {
            sums.load(state);
            passes = saved;
        }
    }
    // The photon map's radius as it was after those passes.
    for (int pass = 0; photons && pass < passes; ++pass) photons->shrink_radius(pass);
    const int first = passes;
    Progress progress("path",
                      static_cast<int64_t>(plan.max_passes - first) * static_cast<int64_t>(pixels),
                      options.progress);
    progress.show_rate("samples");
    if (plan.budget) progress.set_budget(options.time_budget);
    for (int pass = first; pass < plan.max_passes; ++pass) {
        const double elapsed = training.seconds + seconds_since(start);
        if (pass > first && plan.budget && elapsed >= options.time_budget) break;
        if (pass > first && options.cancel && options.cancel->load()) break;
        char status[48];
        if (plan.budget && !options.spp_caps_time) {
            std::snprintf(status, sizeof status, "pass %d", pass + 1);
        } else {
            std::snprintf(status, sizeof status, "pass %d/%d", pass + 1, plan.max_passes);
        }
        progress.set_status(status);
        if (photons) photons->build(pass, options.threads);
        trace_pass(setup, window, pass, training.guide.get(), false, sums, rays, nonfinite,
                   progress);
        ++passes;
        if (options.checkpoint) options.checkpoint->save(passes, sums.flat());
        if (options.on_pass) {
            options.on_pass(passes, training.seconds + seconds_since(start),
                            mean_color(sums, ww, wh, passes));
        }
    }
    progress.finish();

    resolve_window(setup, sums, passes, ww, wh, targets, result);
    result.stats.seconds = seconds_since(start);
    result.stats.rays = rays.load() + (photons ? photons->rays() : 0);
    result.stats.nonfinite = nonfinite.load();
    result.stats.passes = passes;
    return result;
}

}  // namespace

RenderResult PathRenderer::render(const Scene& scene, const RenderOptions& options) {
    const int width = scene.film.width, height = scene.film.height;
    check_film_memory(scene, options);
    auto t0 = Clock::now();
    RtScene rt(scene, scene.render.accel, options.threads, options.accels);
    WavelengthWeights wavelengths;
    const Bounds3 bounds = rt.geometry().bounds();
    float diameter = bounds.empty() ? 1.0f : std::max(glm::length(bounds.extent()), 1e-6f);
    LightSelection selection(rt.lights(), scene, 0.5f * diameter);
    auto photons = std::make_unique<CausticPhotons>(rt, wavelengths, diameter);
    if (!photons->active()) photons.reset();
    auto t1 = Clock::now();

    const bool budget = options.time_budget > 0.0;
    const PassPlan plan{
        budget && !options.spp_caps_time ? static_cast<int>(kMaxSpp) : scene.render.spp, budget};
    // The debug AOVs: the camera rays' cost, cast again, and the bounces of the paths.
    const bool want_cost = wants_debug_aov(options, "bvh_cost");
    const bool want_depth = wants_debug_aov(options, "path_depth");
    if (want_cost) rt.check_counts_cost();
    const CameraRays camera(scene.camera, width, height);
    const bool want_visibility = wants_aov(options, Aov::Visibility) && !scene.lights.empty();
    const PassSetup setup{
        scene,   rt,        selection,  wavelengths,     photons.get(),         camera,
        options, want_cost, want_depth, want_visibility, !options.aovs.empty(), avx2_available()};

    Training training;
    if (scene.render.guiding) train_guide(setup, photons.get(), bounds, plan, training);
    RenderResult all = render_windows(film_window(scene, options), options, [&](const Crop& w) {
        return render_window(setup, photons.get(), training, plan, w);
    });
    all.stats.setup_seconds = std::chrono::duration<double>(t1 - t0).count();
    all.stats.seconds += training.seconds;
    all.stats.rays += training.rays.load();
    all.stats.nonfinite += training.nonfinite.load();
    if (training.guide) {
        char detail[160];
        std::snprintf(
            detail, sizeof detail,
            "guiding: %d training passes, %d regions, %zu directional nodes (field %016llx)",
            training.passes, training.guide->regions(), training.guide->direction_nodes(),
            static_cast<unsigned long long>(training.guide->fingerprint()));
        all.stats.detail = detail;
    }
    return all;
}

}  // namespace svetlo
