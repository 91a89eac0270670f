#include "svetlo/job/pixel_trace_job.h"

#include <cmath>
#include <cstdio>

#include "svetlo/core/error.h"
#include "svetlo/job/engines.h"

namespace svetlo {

namespace {

nlohmann::json vec_json(vec3 v) { return {v.x, v.y, v.z}; }

/// A ray's values as {name: number or [numbers]}.
nlohmann::json values_json(const std::vector<TraceValue>& values) {
    nlohmann::json out = nlohmann::json::object();
    for (const TraceValue& v : values) {
        if (v.value.size() == 1)
            out[v.name] = v.value[0];
        else
            out[v.name] = v.value;
    }
    return out;
}

}  // namespace

nlohmann::json trace_json(const PixelTrace& log, const std::string& engine) {
    nlohmann::json rays = nlohmann::json::array();
    for (const TraceRay& r : log.rays) {
        nlohmann::json ray = {{"kind", r.kind},
                              {"parent", r.parent},
                              {"depth", r.depth},
                              {"origin", vec_json(r.origin)},
                              {"direction", vec_json(r.direction)},
                              {"t", std::isfinite(r.t) ? nlohmann::json(r.t) : nlohmann::json()},
                              {"contribution", vec_json(r.contribution)}};
        if (!r.note.empty()) ray["note"] = r.note;
        if (!r.values.empty()) ray["values"] = values_json(r.values);
        rays.push_back(std::move(ray));
    }
    return {{"pixel", {log.x, log.y}},      {"sample", log.sample},    {"engine", engine},
            {"total", vec_json(log.total)}, {"rays", std::move(rays)}, {"notes", log.notes}};
}

PixelTrace trace_job(RenderJob& job, int x, int y, long long sample, long long spp) {
    Scene& scene = job.scene;
    const std::string file = job.run.scene_file.string();
    const std::string& engine = scene.render.engine;
    // One sample per pixel unless spp says otherwise, as `render --spp 1` (docs/trace.md); a
    // progressive engine's sample K is its pass K, the same whatever the spp, so it renders K + 1
    // passes.
    if (capabilities_of(engine, file).progressive) spp = std::max(spp, sample + 1);
    if (sample >= spp) {
        throw Error(file, "--sample",
                    "sample " + std::to_string(sample) + " of " + std::to_string(spp) +
                        " per pixel does not exist (--spp sets the samples of " + engine + ")");
    }
    if (!capabilities_of(engine, file).traces_samples && sample > 0)
        throw Error(file, "--sample", engine + "'s trace is of the whole pixel (--sample 0)");
    if (x < 0 || y < 0 || x >= scene.film.width || y >= scene.film.height) {
        char why[160];
        std::snprintf(why, sizeof why, "(%d, %d) lies outside the %d x %d film", x, y,
                      scene.film.width, scene.film.height);
        throw Error(file, "--pixel", why);
    }
    scene.render.spp = static_cast<int>(spp);
    PixelTrace log;
    log.x = x;
    log.y = y;
    log.sample = static_cast<int>(sample);
    job.options.crop = Crop{x, x + 1, y, y + 1};
    job.options.trace = &log;
    make_renderer(engine, file)->render(scene, job.options);
    job.options.trace = nullptr;
    if (!log.recorded)
        throw Error(file, "--pixel",
                    "the " + engine + " engine does not trace pixels in this version");
    return log;
}

}  // namespace svetlo
