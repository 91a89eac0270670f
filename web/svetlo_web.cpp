// svetlo in the browser (docs/web.md): the job layer bound to JavaScript with embind. The
// page's script (web/page/backend.js) calls these in a worker of its own
// (web/page/render_worker.js), and makes of them
//   - the `svetlo` object of the contract: svetlo.render(SCENE, {engine, width, height, spp,
//     seed, threads, set}). A scene is a file's name in /scenes (the module's working folder:
//     the bundled scenes and the visitor's files) or a scene's JSON text; every option becomes
//     an override by the job layer's rules (job/overrides.h), as the command line's flags and
//     Python's keywords do;
//   - the viewer's requests (`Viewer`): the job layer's ViewerApi over /scenes, the one that
//     answers svetlo serve's page, so that the page is svetlo serve's viewer.
#include <emscripten/bind.h>
#include <emscripten/heap.h>
#include <emscripten/val.h>
#include <malloc.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "svetlo/core/error.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/render_job.h"
#include "svetlo/job/viewer_api.h"

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

/// Refuses, with the one-line error naming the film, a render that would take more memory
/// than the module has left below its WebAssembly memory's limit (the tab would crash).
void check_memory(const RenderJob& job, const std::string& file) {
    const uint64_t limit = emscripten_get_heap_max();
    const uint64_t used = static_cast<uint64_t>(mallinfo().uordblks);
    const uint64_t left = limit > used ? limit - used : 0;
    const uint64_t needs = estimated_render_bytes(job);
    if (needs <= left) return;
    char why[256];
    std::snprintf(why, sizeof why,
                  "a %d x %d render in %s needs about %llu MiB; the page has %llu MiB left "
                  "(its WebAssembly memory's limit is %llu MiB): ask for a smaller film",
                  job.scene.film.width, job.scene.film.height, job.scene.render.engine.c_str(),
                  static_cast<unsigned long long>(needs >> 20),
                  static_cast<unsigned long long>(left >> 20),
                  static_cast<unsigned long long>(limit >> 20));
    throw Error(file, "film", why);
}

/// An image as a Float32Array of linear RGB, top row first (a copy, in JavaScript's memory).
val pixels_of(const Image& image) {
    const size_t floats = image.pixels.size() * 3;
    val pixels = val::global("Float32Array").new_(floats);
    pixels.call<void>("set", val(emscripten::typed_memory_view(
                                 floats, reinterpret_cast<const float*>(image.pixels.data()))));
    return pixels;
}

/// A render of the page. `cancel_at` is the address of a flag in the module's memory
/// (cancel_flag) that the page sets to end a progressive render after the pass in progress
/// (0: none); `on_pass`, when a function, is called after each pass of a progressive engine
/// with {passes, seconds, width, height, pixels}.
val render_scene(const std::string& scene, bool is_text, const std::string& options_text,
                 uintptr_t cancel_at, val on_pass) {
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
        check_memory(job, file);
        if (cancel_at != 0) job.options.cancel = reinterpret_cast<std::atomic<bool>*>(cancel_at);
        if (on_pass.typeOf().as<std::string>() == "function") {
            job.options.on_pass = [&on_pass](int passes, double seconds, const Image& image) {
                val pass = val::object();
                pass.set("passes", passes);
                pass.set("seconds", seconds);
                pass.set("width", image.width);
                pass.set("height", image.height);
                pass.set("pixels", pixels_of(image));
                on_pass(pass);
            };
        }
        const auto t0 = std::chrono::steady_clock::now();
        const RenderResult result = run_job(job);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const Image& image = result.color;
        out.set("width", image.width);
        out.set("height", image.height);
        out.set("seconds", seconds);
        out.set("passes", reached_spp(job, result));
        out.set("cancelled", job.options.cancel != nullptr && job.options.cancel->load());
        out.set("pixels", pixels_of(image));
    } catch (const std::exception& e) {
        out.set("error", std::string(e.what()));
    }
    return out;
}

/// `size` bytes as a Uint8Array (a copy, in JavaScript's memory).
val bytes_of(const char* data, size_t size) {
    val bytes = val::global("Uint8Array").new_(size);
    bytes.call<void>(
        "set", val(emscripten::typed_memory_view(size, reinterpret_cast<const uint8_t*>(data))));
    return bytes;
}

/// A viewer's answer as JavaScript reads it: {status, type, headers: {NAME: VALUE}, body: a
/// Uint8Array (a copy)}.
val response_of(const ViewerResponse& r) {
    val out = val::object();
    out.set("status", r.status);
    out.set("type", r.type);
    val headers = val::object();
    for (const auto& [name, value] : r.headers) headers.set(name, value);
    out.set("headers", headers);
    out.set("body", bytes_of(r.body.data(), r.body.size()));
    return out;
}

/// The viewer's requests in the page (docs/web.md, "The viewer"): svetlo serve's API answered
/// by the same ViewerApi over the module's scene folder, its renders checked against the
/// module's memory. `cancel_at` is the page's flag (cancel_flag), which ends a render after its
/// pass.
class Viewer {
public:
    explicit Viewer(const std::string& target) : api_(target) {
        api_.set_job_check(
            [](const RenderJob& job) { check_memory(job, job.run.scene_file.string()); });
    }

    val get(const std::string& target, uintptr_t cancel_at) {
        return response_of(api_.get(target, flag_at(cancel_at)));
    }

    /// /api/progressive: its bytes handed to `on_bytes` (a Uint8Array each) as they come;
    /// then the answer, whose body is empty unless the request was refused.
    val stream(const std::string& target, uintptr_t cancel_at, val on_bytes) {
        ProgressiveRender render = api_.start_progressive(target, flag_at(cancel_at));
        if (!render.job) return response_of(render.failed);
        api_.run_progressive(render, [&on_bytes](std::string_view bytes) {
            on_bytes(bytes_of(bytes.data(), bytes.size()));
            return true;
        });
        return response_of({200, "application/octet-stream", {}, {}});
    }

private:
    static const std::atomic<bool>* flag_at(uintptr_t at) {
        return at == 0 ? nullptr : reinterpret_cast<const std::atomic<bool>*>(at);
    }
    ViewerApi api_;
};

/// The address of a new flag in the module's memory, cleared, for render_scene's cancel_at:
/// the page holds the memory (a SharedArrayBuffer where the module has threads) and sets the
/// flag's byte to end a render after its pass. Made once per worker; never freed.
uintptr_t cancel_flag() { return reinterpret_cast<uintptr_t>(new std::atomic<bool>(false)); }

/// Clears the flag before a render.
void clear_cancel_flag(uintptr_t at) { reinterpret_cast<std::atomic<bool>*>(at)->store(false); }

}  // namespace

EMSCRIPTEN_BINDINGS(svetlo) {
    emscripten::function("render", &render_scene);
    emscripten::function("cancelFlag", &cancel_flag);
    emscripten::function("clearCancelFlag", &clear_cancel_flag);
    emscripten::class_<Viewer>("Viewer")
        .constructor<std::string>()
        .function("get", &Viewer::get)
        .function("stream", &Viewer::stream);
}
