#include "svetlo/radiosity/radiosity_engine.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"
#include "svetlo/core/sampling.h"
#include "svetlo/geometry/ray.h"
#include "svetlo/radiosity/adaptive_subdivision.h"
#include "svetlo/radiosity/display.h"
#include "svetlo/radiosity/light_shooting.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/draw_pass.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/camera.h"
#include "svetlo/shading/bsdf.h"

namespace svetlo {

namespace {

/// Rays toward the background per point (its cosine-weighted open fraction).
constexpr int kSkyRays = 8;

/// The irradiance the lights and the background give node id straight, per side: the mean
/// over `samples` stratified points of the node.
Sides light_on_node(const PatchMesh& mesh, uint32_t id, uint64_t seed) {
    const ElementTree& tree = *mesh.tree;
    const ElementNode& e = tree.node(id);
    Sides out;
    if (!(e.area > 0.0f)) return out;
    const int points = mesh.settings.samples;
    Rng rng(mix64(seed), id);
    uint64_t rays = 0;
    for (int k = 0; k < points; ++k) {
        vec2 b = points == 1 ? vec2(1.0f / 3.0f)
                             : sample_triangle(stratified_sample(k, points, rng.next_2d()));
        vec3 x = tree.point(id, b);
        for (int side = 0; side < 2; ++side) {
            vec3 n = side == 0 ? tree.normal(id) : -tree.normal(id);
            Color E =
                light_irradiance(mesh.lights, *mesh.accel, x, n, LightSources::Delta, 1, rng, rays);
            // The background as a uniform environment.
            E += sky_irradiance(*mesh.accel, mesh.environment, x, n, kSkyRays, rng);
            out.v[side] += E / static_cast<float>(points);
        }
    }
    return out;
}

/// The sub-pixel position of display pass `s` of `count`: the pixel centre for one.
vec2 pass_jitter(int s, int count, uint64_t seed) {
    if (count == 1) return vec2(0.5f);
    Rng rng(mix64(seed ^ 0x5eedULL), static_cast<uint64_t>(s));
    return stratified_sample(s, count, rng.next_2d());
}

/// svetlo trace: the camera sample `at` of the display, on root triangle t, and how its
/// radiance L = L_e + rho / pi (E + E_ambient) was made.
void log_display_sample(PixelTrace& log, const Scene& scene, const ElementTree& tree,
                        const Ray& ray, const DisplaySample& at, uint32_t t, uint32_t material,
                        float patch_size, Color emitted, Color irradiance, Color ambient, Color rho,
                        Color L) {
    TraceRay r;
    r.kind = "camera";
    r.origin = ray.o;
    r.direction = glm::normalize(ray.d);
    r.t = at.distance;
    r.contribution = L;
    vec3 local;
    const uint32_t element = tree.locate(t, at.b, local);
    const uint32_t patch = tree.locate(t, at.b, local, tree.level_for(t, patch_size));
    describe_hit(r, scene.material_names, material, at.x, at.n, at.side == 0);
    r.set("element", {static_cast<float>(element)})
        .set("patch", {static_cast<float>(patch)})
        .set("emitted", emitted)
        .set("irradiance", irradiance)
        .set("ambient_irradiance", ambient)
        .set("reflectance", rho);
    log.add(std::move(r));
    log.notes.push_back("L = L_e + rho / pi (E + E_ambient), E from the solution at the element");
}

/// svetlo trace: a display sample that meets nothing and shows the background.
void log_background_sample(PixelTrace& log, const CameraRays& camera, int i, int j, vec2 jitter,
                           const Scene& scene) {
    const Ray ray = camera.generate((static_cast<float>(i) + jitter.x) / scene.film.width,
                                    (static_cast<float>(j) + jitter.y) / scene.film.height);
    TraceRay r;
    r.kind = "camera";
    r.origin = ray.o;
    r.direction = glm::normalize(ray.d);
    r.contribution = scene.render.background;
    r.note = "the background";
    log.add(std::move(r));
    record_total(log, scene.render.background, true);
}

/// Step 1: the elements. Uniform, then split where the direct light changes fast; the
/// hierarchical solver links nodes at any level of this tree and may split the leaves
/// further. Returns the rays traced.
uint64_t make_elements(PatchMesh& mesh, const Scene& scene, int threads) {
    mesh.subdivide_uniform();
    return subdivide_adaptive(mesh, std::max(scene.render.light_samples, mesh.settings.samples),
                              scene.render.seed, threads);
}

/// Step 2: the solution, by the chosen solver (solver.h). `on_snapshot`, when set, is shown
/// the progressive solver's solution as it stands along the way.
Solution solve(PatchMesh& mesh, const Scene& scene, const RenderOptions& options,
               Progress& progress, std::function<void(const Solution&)> on_snapshot) {
    const uint64_t seed = scene.render.seed;
    SolverInput input{*mesh.tree,
                      *mesh.accel,
                      mesh.list,
                      mesh.settings,
                      FormFactorContext{*mesh.tree, *mesh.accel, mesh.settings.form_factors,
                                        mesh.settings.samples},
                      [&](uint32_t id) { return light_on_node(mesh, id, seed); },
                      seed,
                      options.threads,
                      &progress,
                      scene.path.string(),
                      std::move(on_snapshot),
                      options.group,
                      options.checkpoint,
                      options.cancel};
    switch (mesh.settings.solver) {
        case RadiositySolver::Jacobi:
            return solve_matrix(input, false);
        case RadiositySolver::GaussSeidel:
            return solve_matrix(input, true);
        case RadiositySolver::Hierarchical:
            return solve_hierarchical(input, kMaxRadiosityNodes);
        case RadiositySolver::Auto:  // resolved by PatchMesh
        case RadiositySolver::Progressive:
            break;
    }
    return solve_progressive(input);
}

/// What the display counts, over all its windows.
struct DisplayCounters {
    std::atomic<uint64_t> rays{0}, nonfinite{0};
};

/// What the display of one window reads: the scene, the solution and how it is shown.
struct Display {
    const Scene& scene;
    const RenderOptions& options;
    const PatchMesh& mesh;
    const Solution& sol;
    const IrradianceField& field;
    const CameraRays& camera_rays;
    bool gather;       // render.radiosity.display: gather (the direct light again, per pixel)
    bool aovs;         // AOVs asked for
    bool visibility;   // the visibility AOV among them
    bool patches_aov;  // the patches debug AOV
    // A pixel's size at unit distance (perspective) or its size (orthographic), scene units.
    float pixel_footprint;
};

/// Pixel (i, j)'s sample s (its jitter `jitter`), where the item buffer found triangle t:
/// the radiance B/pi of the solution there (emitted plus reflected irradiance, with gather
/// the direct light traced again), added to `sum` and its AOVs, the patches AOV at s = 0.
void display_sample(const Display& d, int i, int j, int s, vec2 jitter, uint32_t t, glm::dvec3& sum,
                    AovSum& aov_sum, Image& patches_image, uint64_t& rays, uint64_t& nonfinite) {
    const Scene& scene = d.scene;
    const int width = scene.film.width, height = scene.film.height;
    const ElementTree& tree = *d.mesh.tree;
    const size_t pixel = static_cast<size_t>(j) * width + i;
    Ray ray = d.camera_rays.generate((static_cast<float>(i) + jitter.x) / width,
                                     (static_cast<float>(j) + jitter.y) / height);
    const DisplaySample at = sample_on_triangle(d.mesh.list, t, tree.normal(t), ray);
    const vec3 x = at.x, n = at.n;
    const vec2 b = at.b;
    const int side = at.side;
    Bsdf bsdf =
        make_bsdf(d.mesh.lights.materials()[d.mesh.list.material[t]], at.at, scene.textures);
    const Color rho = radiosity_reflectance(bsdf);
    const Color emitted = side == 0 ? bsdf.emission : Color(0.0f);
    IrradianceField::Value E = d.field.at(t, b, side);
    Rng rng = pixel_rng(mix64(scene.render.seed + static_cast<uint64_t>(s)), pixel);
    Color irradiance = E.total;  // W/m^2, the ambient term's aside
    if (d.gather) {
        // Every light and emitter, and the background: what the solution counted as direct.
        Color direct = light_irradiance(d.mesh.lights, *d.mesh.accel, x, n, LightSources::All,
                                        scene.render.light_samples, rng, rays) +
                       sky_irradiance(*d.mesh.accel, d.mesh.environment, x, n, kSkyRays, rng);
        irradiance = E.indirect + direct;
    }
    Color L = emitted + rho * (1.0f / kPi) * (irradiance + d.sol.ambient);
    AovSample aov{0.0f, vec3(0.0f), Color(0.0f), 0.0f};
    if (d.aovs) {
        aov.visibility = d.visibility ? light0_visibility(d.mesh.lights, *d.mesh.accel, x, n,
                                                          scene.render.light_samples, rng, rays)
                                      : 1.0f;
        aov.depth = at.distance;
        aov.normal = n;
        aov.albedo = albedo_of(bsdf);
    }
    const bool finite = is_finite(L) && is_finite(aov.normal) && is_finite(aov.albedo) &&
                        std::isfinite(aov.depth + aov.visibility);
    if (PixelTrace* log = d.options.trace; log && log->at(i, j) && log->sample == s) {
        log_display_sample(*log, scene, tree, ray, at, t, d.mesh.list.material[t],
                           d.mesh.settings.patch_size, emitted, irradiance, d.sol.ambient, rho, L);
        record_total(*log, L, finite);
    }
    // A sample that is not finite is dropped (black) and counted, as in every engine.
    if (!finite) {
        ++nonfinite;
        return;
    }
    sum += glm::dvec3(L);
    if (d.aovs) aov_sum.add(aov);
    if (d.patches_aov && s == 0) {
        // Lines about a pixel wide: the pixel's footprint at the point.
        const float footprint = scene.camera.type == Camera::Type::Perspective
                                    ? d.pixel_footprint * at.distance
                                    : d.pixel_footprint;
        patches_image.at(i, j) =
            patches_view(tree, t, b, side, d.sol.E, rho, d.mesh.settings.patch_size, footprint);
    }
}

/// The image and AOVs: the sums of `spp` samples per pixel, averaged.
void write_means(RenderResult& result, const AovTargets& targets,
                 const std::vector<glm::dvec3>& sums, const std::vector<AovSum>& aov_sums,
                 int spp) {
    const int width = result.color.width, height = result.color.height;
    const float inv = 1.0f / static_cast<float>(spp);
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const size_t pixel = static_cast<size_t>(j) * width + i;
            Color c(sums[pixel] * static_cast<double>(inv));
            result.color.at(i, j) = c;
            if (targets.any) targets.write(i, j, aov_sums[pixel].mean(spp));
        }
    }
}

/// Step 3: one window of the display. spp item-buffer passes of the scene's triangles, each
/// jittered within the pixel, and per sample L = L_e + rho / pi E from the field (display.h).
/// The item buffer is drawn whole; only the window's pixels are gathered.
RenderResult display_window(const Scene& scene, const RenderOptions& options, const PatchMesh& mesh,
                            const Solution& sol, const IrradianceField& field, const Crop& window,
                            DisplayCounters& counters) {
    const int width = scene.film.width, height = scene.film.height;
    const int threads = options.threads;
    const uint64_t seed = scene.render.seed;
    RenderResult result;
    const AovTargets targets = prepare_result(result, options.aovs, width, height);
    const bool patches_aov = wants_debug_aov(options, "patches");
    Image patches_image;
    if (patches_aov) patches_image = Image(width, height);
    const int spp = scene.render.spp;
    std::vector<glm::dvec3> sums(static_cast<size_t>(width) * height, glm::dvec3(0.0));
    std::vector<AovSum> aov_sums(targets.any ? sums.size() : 0);
    const CameraMatrices camera = frame_camera(scene, mesh.list, threads);
    const CameraRays camera_rays(scene.camera, width, height);
    const Display display{
        scene,
        options,
        mesh,
        sol,
        field,
        camera_rays,
        mesh.settings.display == RadiosityDisplay::Gather,
        targets.any,
        targets.want(Aov::Visibility),
        patches_aov,
        scene.camera.type == Camera::Type::Perspective
            ? 2.0f * std::tan(0.5f * radians(scene.camera.fov_deg)) / static_cast<float>(height)
            : scene.camera.height / static_cast<float>(height)};
    RenderTargets buffers;
    PassMemory memory;
    AovSum no_aov;
    // Alpha's holes (raster/alpha_test.h): the camera sees through them.
    const raster::AlphaTest alpha(mesh.lights.materials(), scene.textures);
    for (int s = 0; s < spp; ++s) {
        const vec2 jitter = pass_jitter(s, spp, seed);
        buffers.clear(width, height, 1, false, true);
        PipelineState state;
        if (alpha.any()) state.alpha = &alpha;
        draw_pass(mesh.list, jittered_camera(camera, jitter), state, buffers, threads, 0, &memory);
        parallel_tiles(width, height, threads, [&](const Tile& tile) {
            uint64_t local_rays = 0, local_nonfinite = 0;
            for (int j = tile.y0; j < tile.y1; ++j) {
                for (int i = tile.x0; i < tile.x1; ++i) {
                    if (i < window.x0 || i >= window.x1 || j < window.y0 || j >= window.y1)
                        continue;
                    const size_t pixel = static_cast<size_t>(j) * width + i;
                    const uint32_t t = buffers.primitive[buffers.index(i, j)];
                    if (t != RenderTargets::kNoPrimitive) {
                        display_sample(display, i, j, s, jitter, t, sums[pixel],
                                       targets.any ? aov_sums[pixel] : no_aov, patches_image,
                                       local_rays, local_nonfinite);
                        continue;
                    }
                    if (PixelTrace* log = options.trace; log && log->at(i, j) && log->sample == s)
                        log_background_sample(*log, camera_rays, i, j, jitter, scene);
                    // What comes from far away along the pixel's ray.
                    const Ray away =
                        camera_rays.generate((static_cast<float>(i) + jitter.x) / width,
                                             (static_cast<float>(j) + jitter.y) / height);
                    sums[pixel] += glm::dvec3(mesh.environment.radiance(glm::normalize(away.d)));
                    if (targets.any) aov_sums[pixel].visibility += 1.0;
                }
            }
            counters.rays += local_rays;
            counters.nonfinite += local_nonfinite;
        });
    }
    write_means(result, targets, sums, aov_sums, spp);
    if (patches_aov) result.aovs["patches"] = std::move(patches_image);
    cut_to_window(result, window, width, height);
    return result;
}

/// The irradiance field of a solution: whole, and its indirect part (display.h).
IrradianceField field_of(const ElementTree& tree, const Solution& sol) {
    std::vector<Sides> indirect(sol.E.size());
    for (size_t id = 0; id < sol.E.size(); ++id)
        for (int s = 0; s < 2; ++s)
            indirect[id].v[s] = glm::max(sol.E[id].v[s] - sol.direct[id].v[s], Color(0.0f));
    return IrradianceField(tree, sol.E, indirect);
}

/// The summary line's account of the mesh and the solver.
std::string solver_detail(const ElementTree& tree, const RadiositySettings& settings,
                          const Solution& sol, const RenderStats& stats) {
    size_t leaves = 0;
    for (const ElementNode& n : tree.nodes()) leaves += n.leaf() ? 1 : 0;
    char solver[96];
    if (settings.solver == RadiositySolver::Progressive) {
        std::snprintf(solver, sizeof solver, "%zu patches, %d shots, %.1f MiB of rows", sol.patches,
                      sol.iterations, static_cast<double>(sol.cache_bytes) / (1 << 20));
    } else {
        std::snprintf(solver, sizeof solver, "%d sweeps, %llu links", sol.iterations,
                      static_cast<unsigned long long>(sol.links));
    }
    char detail[224];
    std::snprintf(detail, sizeof detail, "%zu elements, %s, residual %.2g, %.2f Mrays/s", leaves,
                  solver, sol.residual,
                  static_cast<double>(stats.rays) * 1e-6 / std::max(stats.seconds, 1e-9));
    return detail;
}

}  // namespace

RenderResult RadiosityRenderer::render(const Scene& scene, const RenderOptions& options) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    PatchMesh mesh(scene, options.threads);
    if (options.checkpoint && mesh.settings.solver != RadiositySolver::Progressive) {
        throw Error(scene.path.string(), "--checkpoint",
                    "the radiosity solve is checkpointed by the progressive solver only "
                    "(render.radiosity.solver=progressive), not by " +
                        std::string(name_of(kRadiositySolvers, mesh.settings.solver)));
    }
    uint64_t rays = make_elements(mesh, scene, options.threads);
    const auto t1 = Clock::now();

    DisplayCounters display;
    // With on_pass (compare --curves, --mse-log), each snapshot of the solver is displayed
    // and shown at the solver's seconds: the displays of snapshots, which the render without
    // them would not have made, are left out of every time.
    std::function<void(const Solution&)> on_snapshot;
    double shown = 0.0;  // seconds spent displaying snapshots
    if (options.on_pass && !options.windows) {
        on_snapshot = [&](const Solution& partial) {
            const auto before = Clock::now();
            DisplayCounters ignored;
            const RenderResult image =
                display_window(scene, options, mesh, partial, field_of(*mesh.tree, partial),
                               film_window(scene, options), ignored);
            options.on_pass(scene.render.spp,
                            std::chrono::duration<double>(before - t1).count() - shown,
                            image.color);
            shown += std::chrono::duration<double>(Clock::now() - before).count();
        };
    }
    Progress progress("radiosity", 1, options.progress);
    const Solution sol = solve(mesh, scene, options, progress, std::move(on_snapshot));
    rays += sol.rays;
    progress.finish();

    const IrradianceField field = field_of(*mesh.tree, sol);
    RenderResult result =
        render_windows(film_window(scene, options), options, [&](const Crop& window) {
            return display_window(scene, options, mesh, sol, field, window, display);
        });
    const auto t2 = Clock::now();
    result.stats.setup_seconds = std::chrono::duration<double>(t1 - t0).count();
    result.stats.seconds = std::chrono::duration<double>(t2 - t1).count() - shown;
    result.stats.rays = rays + display.rays.load();
    result.stats.nonfinite = display.nonfinite.load();
    result.stats.detail = solver_detail(*mesh.tree, mesh.settings, sol, result.stats);
    return result;
}

}  // namespace svetlo
