// svetlo render SCENE.json [-o OUT] [--engine E] [--width W] [--height H] [--spp N]
//               [--time SECONDS] [--threads N] [--seed S] [--set KEY=VALUE]... [--aov NAME=FILE]...
//               [--quiet]
#include <algorithm>
#include <cstdio>

#include "commands.h"
#include "engines.h"
#include "flags.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"

namespace svetlo {

std::vector<Override> parse_sets(const std::vector<std::string>& sets, const std::string& file) {
    std::vector<Override> out;
    for (const std::string& s : sets) {
        size_t eq = s.find('=');
        if (eq == std::string::npos || eq == 0) {
            throw Error(file, "--set " + s, "expected KEY=VALUE");
        }
        out.push_back({s.substr(0, eq), s.substr(eq + 1)});
    }
    return out;
}

void add_flag_overrides(const std::string& file, const std::string& width,
                        const std::string& height, std::vector<Override>& overrides) {
    if (!width.empty()) {
        overrides.push_back(
            {"film.width", std::to_string(flag_integer(file, "-W", width, 1, kMaxFilmSide))});
    }
    if (!height.empty()) {
        overrides.push_back(
            {"film.height", std::to_string(flag_integer(file, "-H", height, 1, kMaxFilmSide))});
    }
}

int flag_threads(const std::string& file, const std::string& text) {
    return text.empty() ? 0 : static_cast<int>(flag_integer(file, "-t", text, 0, kMaxThreads));
}

int run_render(const RenderArgs& args) {
    std::vector<Override> overrides = parse_sets(args.sets, args.scene);
    // The flags override the scene and any --set.
    if (!args.engine.empty()) overrides.push_back({"render.engine", "\"" + args.engine + "\""});
    add_flag_overrides(args.scene, args.width, args.height, overrides);
    if (!args.spp.empty()) {
        overrides.push_back({"render.spp", std::to_string(flag_integer(args.scene, "--spp",
                                                                       args.spp, 1, kMaxSpp))});
    }
    if (!args.seed.empty()) {
        overrides.push_back({"render.seed", std::to_string(flag_integer(args.scene, "--seed",
                                                                        args.seed, 0, kMaxSeed))});
    }
    const int threads = flag_threads(args.scene, args.threads);
    const double time_budget = flag_seconds(args.scene, "--time", args.time);

    // Check every output before the (possibly long) render.
    check_writable(args.output, "-o");
    std::vector<std::pair<std::string, std::string>> aovs;
    for (const std::string& spec : args.aovs) {
        size_t eq = spec.find('=');
        std::string name = spec.substr(0, eq);
        if (eq == std::string::npos || eq + 1 == spec.size()) {
            throw Error(spec, "--aov", "expected NAME=FILE");
        }
        const auto& names = aov_names();
        const auto& debug = debug_aov_names();
        if (std::find(names.begin(), names.end(), name) == names.end() &&
            std::find(debug.begin(), debug.end(), name) == debug.end()) {
            throw Error(spec, "--aov",
                        "unknown AOV '" + name +
                            "' (expected depth, normal, albedo, visibility, shadow_map, stencil or "
                            "patches)");
        }
        aovs.emplace_back(name, spec.substr(eq + 1));
        check_writable(aovs.back().second, "--aov " + name);
    }
    // Two outputs to one file: the later would overwrite the earlier.
    auto same_file = [](const std::string& a, const std::string& b) {
        std::error_code ec;
        return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
    };
    for (size_t k = 0; k < aovs.size(); ++k) {
        const auto& [name, file] = aovs[k];
        if (same_file(file, args.output))
            throw Error(file, "--aov " + name, "is also the image's file (-o)");
        for (size_t m = 0; m < k; ++m) {
            if (same_file(file, aovs[m].second))
                throw Error(file, "--aov " + name, "is also the file of --aov " + aovs[m].first);
        }
    }

    Scene scene = load_scene(args.scene, overrides);
    std::unique_ptr<Renderer> renderer = make_renderer(scene.render.engine, args.scene);
    if (time_budget > 0.0 && scene.render.engine != "path") {
        throw Error(args.scene, "--time",
                    "needs a progressive engine (path); " + scene.render.engine + " is not one");
    }
    RenderOptions options;
    options.threads = threads;
    options.time_budget = time_budget;
    options.spp_caps_time = !args.spp.empty();  // the scene's spp does not cap --time
    options.progress = !args.quiet && stderr_is_terminal();
    for (const auto& [name, file] : aovs) {
        if (name == "patches") {
            if (scene.render.engine != "radiosity")
                throw Error(file, "--aov patches", "needs render.engine radiosity");
            options.debug_aovs.push_back(name);
            continue;
        }
        if (name != "shadow_map" && name != "stencil") {
            options.aovs.push_back(name);
            continue;
        }
        // The rasterizer's teaching buffers exist for one technique each.
        const ShadowTechnique needs =
            name == "shadow_map" ? ShadowTechnique::Map : ShadowTechnique::Volume;
        if (scene.render.engine != "raster" || scene.render.shadows != needs) {
            throw Error(file, "--aov " + name,
                        "needs render.engine raster with render.shadows " +
                            std::string(name_of(kShadowTechniques, needs)));
        }
        options.debug_aovs.push_back(name);
    }
    RenderResult result = renderer->render(scene, options);

    write_image(args.output, result.color, PixelMeaning::Radiance, scene.render.exposure, "-o");
    for (const auto& [name, file] : aovs) {
        Image image = result.aovs.at(name);
        bool png = image_format_for(file, "--aov") == ImageFormat::Png;
        if (png && name == "normal") {
            for (Color& c : image.pixels) c = 0.5f * c + Color(0.5f);  // [-1,1] -> [0,1]
        } else if (png && name == "stencil") {
            // Counts of a few: scaled by the largest magnitude, so that 1 is visible.
            float most = 0.0f;
            for (const Color& c : image.pixels) most = std::max(most, std::abs(c.r));
            if (most > 0.0f) {
                for (Color& c : image.pixels) c = glm::abs(c) / most;
            }
        } else if (png && (name == "depth" || name == "shadow_map")) {
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
        write_image(file, image, name == "albedo" ? PixelMeaning::Radiance : PixelMeaning::Data,
                    1.0f, "--aov " + name);
    }
    if (!args.quiet) {
        double per_second = result.stats.seconds > 0.0 ? 1e-6 / result.stats.seconds : 0.0;
        char rate[160];
        if (!result.stats.detail.empty()) {  // the engine's own account
            std::snprintf(rate, sizeof rate, "%s", result.stats.detail.c_str());
        } else if (result.stats.triangles > 0) {
            std::snprintf(rate, sizeof rate, "%.2f Mtris/s",
                          static_cast<double>(result.stats.triangles) * per_second);
        } else if (result.stats.passes > 0) {  // a path per pixel and pass
            double paths = static_cast<double>(result.stats.passes) * scene.film.width *
                           static_cast<double>(scene.film.height);
            std::snprintf(rate, sizeof rate, "%.2f Mpaths/s, %.2f Mrays/s", paths * per_second,
                          static_cast<double>(result.stats.rays) * per_second);
        } else {
            std::snprintf(rate, sizeof rate, "%.2f Mrays/s",
                          static_cast<double>(result.stats.rays) * per_second);
        }
        std::string dropped;  // samples that were not finite, left out of their pixels
        if (result.stats.nonfinite > 0)
            dropped = ", " + std::to_string(result.stats.nonfinite) + " non-finite samples dropped";
        std::fprintf(
            stderr,
            "svetlo: %s %dx%d, %d spp, %d threads: setup %.3f s, render %.3f s, %s%s -> %s\n",
            scene.render.engine.c_str(), scene.film.width, scene.film.height,
            result.stats.passes > 0 ? result.stats.passes : scene.render.spp,
            resolve_threads(threads), result.stats.setup_seconds, result.stats.seconds, rate,
            dropped.c_str(), args.output.c_str());
    }
    return 0;
}

}  // namespace svetlo
