#include "svetlo/job/render_job.h"

#include <algorithm>
#include <cstdio>

#include "svetlo/core/atomic_file.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/image_metrics.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/limits.h"

namespace svetlo {

RenderJob make_job(nlohmann::json json, const std::filesystem::path& path, std::string sha256,
                   FileCache* meshes, const FileScope& files) {
    RenderJob job;
    job.scene = scene_from_json(json, path, meshes, files);
    capabilities_of(job.scene.render.engine, path.string());  // an unknown engine: one line
    for (const std::string& w : job.scene.warnings)
        std::fprintf(stderr, "svetlo: warning: %s: %s\n", path.string().c_str(), w.c_str());
    job.run.scene_file = path;
    job.run.scene_sha256 = std::move(sha256);
    job.run.scene = std::move(json);
    return job;
}

void set_time_budget(RenderJob& job, double seconds, const std::string& file,
                     const std::string& key) {
    char shown[48];
    std::snprintf(shown, sizeof shown, "%g", seconds);
    if (!std::isfinite(seconds) || !(seconds > 0.0) || seconds > kMaxSeconds)
        throw Error(
            file, key,
            std::string("must be a number of seconds in (0, 604800], a week (is ") + shown + ")");
    const Capabilities& engine = capabilities_of(job.scene.render.engine, file);
    if (!engine.progressive)
        throw Error(file, key,
                    "needs a progressive engine (" +
                        engines_with([](const Capabilities& c) { return c.progressive; }) + "); " +
                        engine.name + " is not one");
    job.options.time_budget = seconds;
}

Crop parse_crop(const std::string& text, const std::string& file, int width, int height) {
    long long v[4];
    size_t start = 0;
    for (int k = 0; k < 4; ++k) {
        size_t comma = text.find(',', start);
        if ((k < 3) != (comma != std::string::npos))
            throw Error(file, "--crop", "expected X0,X1,Y0,Y1 (is '" + text + "')");
        std::string part = text.substr(start, k < 3 ? comma - start : std::string::npos);
        v[k] = flag_integer(file, "--crop", part, 0, kMaxFilmSide);
        start = comma + 1;
    }
    Crop c{static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]),
           static_cast<int>(v[3])};
    char why[160];
    if (c.x1 <= c.x0 || c.y1 <= c.y0) {
        std::snprintf(why, sizeof why, "the window %s is empty (X0 < X1 and Y0 < Y1 needed)",
                      text.c_str());
        throw Error(file, "--crop", why);
    }
    if (c.x1 > width || c.y1 > height) {
        std::snprintf(why, sizeof why, "the window %s leaves the %d x %d film", text.c_str(), width,
                      height);
        throw Error(file, "--crop", why);
    }
    return c;
}

void request_aov(RenderJob& job, const std::string& name, const std::string& file,
                 const std::string& where) {
    const std::vector<std::string>& plain = aov_names();
    const std::vector<std::string> debug = debug_aov_names();
    if (std::find(plain.begin(), plain.end(), name) != plain.end()) {
        job.options.aovs.push_back(name);
        return;
    }
    if (std::find(debug.begin(), debug.end(), name) == debug.end()) {
        std::string known;
        for (const std::string& n : plain) known += n + ", ";
        for (const std::string& n : debug) known += n + (n == debug.back() ? "" : ", ");
        throw Error(file, where, "unknown AOV '" + name + "' (expected one of " + known + ")");
    }
    // The teaching buffers exist for some engines and techniques each.
    if (std::string why = debug_aov_refusal(job.scene, name); !why.empty())
        throw Error(file, where, why);
    job.options.debug_aovs.push_back(name);
}

void request_aovs(RenderJob& job, const std::vector<std::string>& specs,
                  const std::string& output) {
    for (const std::string& spec : specs) {
        size_t eq = spec.find('=');
        if (eq == std::string::npos || eq + 1 == spec.size()) {
            throw Error(spec, "--aov", "expected NAME=FILE");
        }
        job.aov_files.emplace_back(spec.substr(0, eq), spec.substr(eq + 1));
    }
    // Two outputs to one file: the later would overwrite the earlier.
    auto same_file = [](const std::string& a, const std::string& b) {
        std::error_code ec;
        return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
    };
    for (size_t k = 0; k < job.aov_files.size(); ++k) {
        const auto& [name, file] = job.aov_files[k];
        request_aov(job, name, file, "--aov " + name);
        check_writable(file, "--aov " + name);
        if (same_file(file, output))
            throw Error(file, "--aov " + name, "is also the image's file (-o)");
        for (size_t m = 0; m < k; ++m) {
            if (same_file(file, job.aov_files[m].second))
                throw Error(file, "--aov " + name,
                            "is also the file of --aov " + job.aov_files[m].first);
        }
    }
}

RenderResult run_job(const RenderJob& job) {
    std::unique_ptr<Renderer> renderer = make_renderer(job.scene.render.engine, job.run.scene_file);
    return renderer->render(job.scene, job.options);
}

RenderResult run_job(const RenderJob& job, RendererPool& pool) {
    const RendererPool::Lease renderer = pool.take(job.scene.render.engine, job.run.scene_file);
    return renderer->render(job.scene, job.options);
}

int reached_spp(const RenderJob& job, const RenderResult& result) {
    return result.stats.passes > 0 ? result.stats.passes : job.scene.render.spp;
}

Image aov_for_display(const std::string& name, Image image) {
    if (name == "normal") {
        for (Color& c : image.pixels) c = 0.5f * c + Color(0.5f);  // [-1,1] -> [0,1]
    } else if (name == "stencil") {
        // Counts of a few: scaled by the largest magnitude, so that 1 is visible.
        float most = 0.0f;
        for (const Color& c : image.pixels) most = std::max(most, std::abs(c.r));
        if (most > 0.0f) {
            for (Color& c : image.pixels) c = glm::abs(c) / most;
        }
    } else if (name == "bvh_cost" || name == "path_depth") {
        // A heat map (magma) of the count (for bvh_cost, nodes plus primitives) up to its
        // 99th percentile, so that a few costly pixels do not leave the rest dark.
        std::vector<float> counts;
        for (const Color& c : image.pixels) counts.push_back(name == "bvh_cost" ? c.b : c.r);
        std::vector<float> sorted = counts;
        auto k = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() * 99 / 100);
        std::nth_element(sorted.begin(), k, sorted.end());
        image = false_color(counts, image.width, image.height, std::max(*k, 1.0f));
    } else if (name == "depth" || name == "shadow_map") {
        // Normalised by the 90th percentile of the hits' depths, not the farthest hit: an
        // infinite plane's horizon, thousands of units away, would leave the rest black.
        // Farther hits are white.
        std::vector<float> hits;
        for (const Color& c : image.pixels) {
            if (c.r > 0.0f) hits.push_back(c.r);
        }
        if (!hits.empty()) {
            auto k = hits.begin() + static_cast<std::ptrdiff_t>(hits.size() * 9 / 10);
            std::nth_element(hits.begin(), k, hits.end());
            for (Color& c : image.pixels) c = glm::min(c / *k, Color(1.0f));
        }
    }
    return image;
}

std::string job_provenance(const RenderJob& job, const RenderResult& result,
                           const std::string& image) {
    RunRecord run = job.run;
    run.image = image;
    return make_provenance(run, job.scene, job.options, result.stats, reached_spp(job, result))
        .dump();
}

void write_job_outputs(const RenderJob& job, const RenderResult& result,
                       const std::string& output) {
    if (!output.empty())
        write_image(output, result.color, PixelMeaning::Radiance, job.scene.render.exposure, "-o",
                    job_provenance(job, result));
    for (const auto& [name, file] : job.aov_files) {
        Image image = result.aovs.at(name);
        if (image_format_for(file, "--aov") == ImageFormat::Png)
            image = aov_for_display(name, std::move(image));
        write_image(file, image, name == "albedo" ? PixelMeaning::Radiance : PixelMeaning::Data,
                    1.0f, "--aov " + name, job_provenance(job, result, name));
    }
}

uint64_t estimated_render_bytes(const RenderJob& job) {
    const Crop window = film_window(job.scene, job.options);
    const uint64_t pixels = static_cast<uint64_t>(window.width()) * window.height();
    const Capabilities& engine =
        capabilities_of(job.scene.render.engine, job.run.scene_file.string());
    const uint64_t aovs = job.options.aovs.size() + job.options.debug_aovs.size();
    return pixels * (static_cast<uint64_t>(engine.film_bytes_per_pixel) + aovs * kAovBytesPerPixel);
}

void write_text_file(const std::string& path, const std::string& text, const std::string& where) {
    try {
        write_file_atomically(path, text);
    } catch (const std::exception& e) {
        throw Error(path, where, std::string("cannot write: ") + e.what());
    }
}

}  // namespace svetlo
