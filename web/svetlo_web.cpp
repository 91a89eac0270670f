// svetlo in the browser (docs/web.md): the job layer bound to JavaScript with embind. The
// page's script (web/page/svetlo.js) calls these in a worker of its own, and makes of them the
// `svetlo` object of the contract: svetlo.render(SCENE, {engine, width, height, spp, seed,
// threads, set}). A scene is a bundled file's name (under /scenes, the module's working
// folder) or a scene's JSON text; every option becomes an override by the job layer's rules
// (job/overrides.h), as the command line's flags and Python's keywords do.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <chrono>
#include <exception>
#include <string>
#include <vector>

#include "svetlo/core/error.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/render_job.h"

using emscripten::val;
using namespace svetlo;

namespace {

/// The name a scene given as text has in messages (its relative files resolve in /scenes).
constexpr const char* kSceneText = "scene.json";

/// A number or a string option as the text a flag would carry ("" when absent).
std::string option_text(const nlohmann::json& options, const char* name) {
    const auto it = options.find(name);
    if (it == options.end() || it->is_null()) return {};
    return it->is_string() ? it->get<std::string>() : it->dump();
}

/// The request's overrides: `set` first (an object of KEY: value, or "KEY=VALUE" strings),
/// then the keys its options stand for.
std::vector<Override> request_overrides(const nlohmann::json& options, const std::string& file) {
    std::vector<Override> overrides;
    if (const auto set = options.find("set"); set != options.end() && !set->is_null()) {
        if (set->is_object()) {
            for (const auto& [key, value] : set->items()) overrides.push_back({key, value.dump()});
        } else if (set->is_array() || set->is_string()) {
            std::vector<std::string> sets;
            for (const auto& entry : set->is_array() ? *set : nlohmann::json::array({*set})) {
                if (!entry.is_string()) throw Error(file, "set", "expected \"KEY=VALUE\" strings");
                sets.push_back(entry.get<std::string>());
            }
            const std::vector<Override> parsed = parse_sets(sets, file);
            overrides.insert(overrides.end(), parsed.begin(), parsed.end());
        } else {
            throw Error(file, "set", "expected an object of KEY: value");
        }
    }
    add_key_overrides(
        file,
        request_keys(kKeywordNames, [&](const char* name) { return option_text(options, name); }),
        kKeywordNames, overrides);
    return overrides;
}

/// The effective scene of a bundled file's name, or of a scene's text.
nlohmann::json effective_json(const std::string& scene, bool is_text,
                              const std::vector<Override>& overrides, const std::string& file) {
    if (!is_text) {
        if (scene.empty() || scene.find("..") != std::string::npos || scene.front() == '/')
            throw Error(scene, "scene", "expected the name of a bundled scene (svetlo.scenes)");
        return effective_scene_json(scene, overrides);
    }
    return scene_text_with_overrides(scene, file, overrides);
}

val render_scene(const std::string& scene, bool is_text, const std::string& options_text) {
    val out = val::object();
    try {
        const std::string file = is_text ? kSceneText : scene;
        nlohmann::json options;
        try {
            options = options_text.empty() ? nlohmann::json::object()
                                           : nlohmann::json::parse(options_text);
        } catch (const nlohmann::json::exception& e) {
            throw Error(file, "options", e.what());
        }
        const std::vector<Override> overrides = request_overrides(options, file);
        RenderJob job = make_job(effective_json(scene, is_text, overrides, file), file, {});
        const std::string threads = option_text(options, "threads");
        job.options.threads =
            threads.empty()
                ? 0
                : static_cast<int>(flag_integer(file, "threads", threads, 0, kMaxThreads));
        const auto t0 = std::chrono::steady_clock::now();
        const RenderResult result = run_job(job);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const Image& image = result.color;
        const size_t floats = image.pixels.size() * 3;
        val pixels = val::global("Float32Array").new_(floats);
        pixels.call<void>("set", val(emscripten::typed_memory_view(
                                     floats, reinterpret_cast<const float*>(image.pixels.data()))));
        out.set("width", image.width);
        out.set("height", image.height);
        out.set("seconds", seconds);
        out.set("pixels", pixels);
    } catch (const std::exception& e) {
        out.set("error", std::string(e.what()));
    }
    return out;
}

/// The engines and what each can do, as the page's controls need them (JSON text).
std::string engines_json() {
    nlohmann::json list = nlohmann::json::array();
    for (const Capabilities& c : engine_capabilities())
        list.push_back({{"name", c.name}, {"progressive", c.progressive}});
    return list.dump();
}

}  // namespace

EMSCRIPTEN_BINDINGS(svetlo) {
    emscripten::function("render", &render_scene);
    emscripten::function("engines", &engines_json);
}
