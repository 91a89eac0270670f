#include "svetlo/job/compare.h"

#include <cstdio>
#include <optional>

#include "svetlo/core/error.h"
#include "svetlo/core/flip.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/progress.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/geometry/triangle_list_cache.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/render_job.h"

namespace svetlo {

ImageComparison compare_images(const Image& test, const Image& reference, bool ldr, int threads) {
    ImageComparison c;
    c.pixels = pixel_metrics(test, reference);
    c.flip = ldr ? flip_ldr(reference, test, kFlipPixelsPerDegree, threads)
                 : flip_hdr(reference, test, kFlipPixelsPerDegree, threads);
    return c;
}

double ImageComparison::value(const std::string& metric) const {
    if (metric == "mae") return pixels.mae;
    if (metric == "rmse") return pixels.rmse;
    if (metric == "relmse") return pixels.relmse;
    return flip.mean;
}

namespace {

/// The overrides of a SPEC: render.engine, then each KEY=VALUE; `aov=NAME` parts go to
/// `aovs` (the buffers the sheet shows beside the image).
std::vector<Override> spec_overrides(const std::string& spec, const std::string& file,
                                     std::vector<std::string>& aovs) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (true) {
        size_t colon = spec.find(':', start);
        parts.push_back(spec.substr(start, colon == std::string::npos ? colon : colon - start));
        if (colon == std::string::npos) break;
        start = colon + 1;
    }
    const std::string& engine = parts[0];
    if (engine.empty()) throw Error(file, "-T " + spec, "expected ENGINE[:KEY=VALUE]...");
    try {
        make_renderer(engine, file);
    } catch (const Error& e) {
        throw Error(file, "-T " + spec, e.message());
    }
    std::vector<Override> out = {{"render.engine", "\"" + engine + "\""}};
    for (size_t k = 1; k < parts.size(); ++k) {
        size_t eq = parts[k].find('=');
        if (eq == std::string::npos || eq == 0)
            throw Error(file, "-T " + spec, "expected KEY=VALUE, not '" + parts[k] + "'");
        if (parts[k].substr(0, eq) == "aov") {
            aovs.push_back(parts[k].substr(eq + 1));
            continue;
        }
        out.push_back({parts[k].substr(0, eq), parts[k].substr(eq + 1)});
    }
    return out;
}

/// What the jobs of one sheet share: the mesh files read, and one BVH for the techniques and
/// the reference whose shapes are the same (docs/compare.md, "One scene, one BVH").
struct SharedSetup {
    FileCache meshes;
    AccelCache accels;
    TriangleListCache triangle_lists;
    OccluderCubeCache occluder_cubes;
};

/// The job of one SPEC over the scene's JSON (already with the command's overrides). Errors
/// name the SPEC.
RenderJob spec_job(const nlohmann::json& base, const std::string& file, const std::string& spec,
                   const std::string& sha256, int threads, SharedSetup& shared) {
    nlohmann::json json = base;
    try {
        std::vector<std::string> aovs;
        for (const Override& o : spec_overrides(spec, file, aovs)) apply_override(json, o, file);
        RenderJob job = make_job(std::move(json), file, sha256, &shared.meshes);
        job.options.threads = threads;
        job.options.accels = &shared.accels;
        job.options.triangle_lists = &shared.triangle_lists;
        job.options.occluder_cubes = &shared.occluder_cubes;
        for (const std::string& name : aovs) request_aov(job, name, file, "-T " + spec);
        return job;
    } catch (const Error& e) {
        if (e.where().rfind("-T ", 0) == 0) throw;
        throw Error(e.file(), "-T " + spec + ": " + e.where(), e.message());
    }
}

/// Renders one technique's job and measures it against the reference (its curve of error
/// against time too, when `curves`).
SheetEntry render_entry(RenderJob& job, const std::string& spec, const Image& reference, bool ldr,
                        int threads, bool curves, bool quiet) {
    SheetEntry e;
    e.spec = spec;
    e.name = technique_name(job.scene.render);
    e.engine = job.scene.render.engine;
    e.exposure = job.scene.render.exposure;
    if (curves) {
        job.options.on_pass = [&](int passes, double seconds, const Image& image) {
            PixelMetrics m =
                pixel_metrics(ldr ? as_8bit_srgb(image, e.exposure) : image, reference);
            e.curve.push_back({passes, seconds, m.rmse, m.relmse});
        };
    }
    if (!quiet) std::fprintf(stderr, "svetlo compare: %s\n", e.spec.c_str());
    job.options.progress = !quiet && stderr_is_terminal();
    RenderResult r = run_job(job);
    job.options.on_pass = nullptr;  // (it points at this entry, returned below)
    e.seconds = r.stats.seconds;
    e.image = std::move(r.color);
    for (const std::string& name : job.options.aovs)
        e.buffers.emplace_back(name, aov_for_display(name, r.aovs.at(name)));
    for (const std::string& name : job.options.debug_aovs)
        e.buffers.emplace_back(name, aov_for_display(name, r.aovs.at(name)));
    e.metrics =
        compare_images(ldr ? as_8bit_srgb(e.image, e.exposure) : e.image, reference, ldr, threads);
    // The last point of an engine that is not progressive (radiosity's snapshots came
    // before it) or its only one.
    if (curves && r.stats.passes == 0) {
        e.curve.push_back(
            {reached_spp(job, r), e.seconds, e.metrics.pixels.rmse, e.metrics.pixels.relmse});
    }
    if (!quiet) {
        std::fprintf(stderr, "  %s: mae %.5g rmse %.5g relmse %.5g flip %.5f, %.3f s\n",
                     e.spec.c_str(), e.metrics.pixels.mae, e.metrics.pixels.rmse,
                     e.metrics.pixels.relmse, e.metrics.flip.mean, e.seconds);
    }
    return e;
}

}  // namespace

Sheet compare_techniques(const nlohmann::json& base, const std::string& file,
                         const std::string& sha256, const std::vector<std::string>& techniques,
                         const std::string& reference_spec, int threads, bool curves, bool quiet) {
    SharedSetup shared;
    std::vector<RenderJob> jobs;
    for (const std::string& spec : techniques)
        jobs.push_back(spec_job(base, file, spec, sha256, threads, shared));

    Sheet sheet;
    sheet.scene = file;
    const std::string reference = reference_spec.empty() ? "path:render.spp=1024" : reference_spec;
    sheet.reference = reference;
    bool ldr = false;
    const Scene& first = jobs.front().scene;
    // The reference: an image, or a job rendered once every technique's film is checked.
    std::optional<RenderJob> reference_job;
    int ref_width = 0, ref_height = 0;
    if (is_image_path(reference)) {
        LoadedImage loaded = read_image(reference, "--reference");
        ref_width = loaded.image.width;
        ref_height = loaded.image.height;
        ldr = loaded.ldr;
        sheet.reference_image = std::move(loaded.image);
        sheet.reference_exposure = ldr ? 1.0f : first.render.exposure;
    } else {
        reference_job = spec_job(base, file, reference, sha256, threads, shared);
        ref_width = reference_job->scene.film.width;
        ref_height = reference_job->scene.film.height;
    }
    for (size_t k = 0; k < jobs.size(); ++k) {
        const Film& film = jobs[k].scene.film;
        if (film.width != ref_width || film.height != ref_height) {
            char why[160];
            std::snprintf(why, sizeof why, "its film is %d x %d; the reference's is %d x %d",
                          film.width, film.height, ref_width, ref_height);
            throw Error(file, "-T " + techniques[k], why);
        }
    }
    if (reference_job) {
        if (!quiet) std::fprintf(stderr, "svetlo compare: reference %s\n", reference.c_str());
        reference_job->options.progress = !quiet && stderr_is_terminal();
        RenderResult r = run_job(*reference_job);
        sheet.reference_image = std::move(r.color);
        sheet.reference_exposure = reference_job->scene.render.exposure;
    }
    for (size_t k = 0; k < jobs.size(); ++k) {
        sheet.entries.push_back(render_entry(jobs[k], techniques[k], sheet.reference_image, ldr,
                                             threads, curves, quiet));
    }
    if (!quiet) {
        std::fprintf(stderr, "svetlo compare: %d scene BVH%s built for the ray-traced renders\n",
                     shared.accels.builds(), shared.accels.builds() == 1 ? "" : "s");
    }
    return sheet;
}

}  // namespace svetlo
