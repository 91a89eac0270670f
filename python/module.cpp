// svetlo._svetlo: the compiled half of the Python module (docs/python.md). Every function
// takes a scene as its effective JSON (text), the path that names it in messages and anchors
// its relative files, and the SHA-256 its provenance records; python/svetlo/__init__.py
// wraps them in Scene, render, diff and trace. The renders run through the command line's
// own code (apps/svetlo: RenderJob, the provenance, the metrics), so an image is bit for bit
// the command line's.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <map>
#include <optional>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/sha256.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/geometry/tessellate.h"
#include "svetlo/geometry/triangle_list.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/interrupt.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/pixel_trace_job.h"
#include "svetlo/job/render_job.h"
#include "svetlo/job/sheet.h"
#include "svetlo/scene/instances.h"
#include "svetlo/shading/light_set.h"

namespace py = pybind11;
using namespace svetlo;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

/// An image as a new H x W x 3 float32 array: one copy, sharing nothing with the renderer.
FloatArray to_array(const Image& image) {
    FloatArray out({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width),
                    py::ssize_t{3}});
    static_assert(sizeof(Color) == 3 * sizeof(float));
    std::memcpy(out.mutable_data(), image.pixels.data(), image.pixels.size() * sizeof(Color));
    return out;
}

/// An H x W x 3 array (any float type, made contiguous float32) as an Image.
Image from_array(const FloatArray& a, const char* name) {
    if (a.ndim() != 3 || a.shape(2) != 3)
        throw py::value_error(std::string(name) + ": expected an H x W x 3 array of RGB");
    Image image(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
    std::memcpy(image.pixels.data(), a.data(), image.pixels.size() * sizeof(Color));
    return image;
}

nlohmann::json parse(const std::string& text, const std::string& path) {
    return scene_text_with_overrides(text, path, {});
}

/// Overrides from Python: (dotted KEY, JSON value text), applied in order as --set's.
using Overrides = std::vector<std::pair<std::string, std::string>>;
/// The keywords that stand for scene keys (engine, width, height, spp, seed), as text: the
/// request keys of the job layer (job/overrides.h), checked and named as Python names them.
using Keywords = std::map<std::string, std::string>;

/// The scene's JSON with `overrides` applied, then `keywords` (they win, as the command
/// line's flags do over its --set).
nlohmann::json with_overrides(const std::string& text, const std::string& path,
                              const Overrides& overrides, const Keywords& keywords = {}) {
    std::vector<Override> list;
    for (const auto& [key, value] : overrides) list.push_back({key, value});
    const RequestKeys keys = request_keys(kKeywordNames, [&](const char* name) {
        const auto it = keywords.find(name);
        return it == keywords.end() ? std::string() : it->second;
    });
    add_key_overrides(path, keys, kKeywordNames, list);
    return scene_text_with_overrides(text, path, list);
}

/// The scene's JSON checked as a scene file is (throws Error, which becomes SceneError).
void validate(const std::string& text, const std::string& path) {
    const Scene scene = scene_from_json(parse(text, path), path);
    capabilities_of(scene.render.engine, path);  // an unknown engine: one line
}

/// The JSON of the scene after `key` (dotted, as --set) is set to `value` (JSON text).
std::string set_key(const std::string& text, const std::string& path, const std::string& key,
                    const std::string& value) {
    const nlohmann::json json = with_overrides(text, path, {{key, value}});
    const Scene scene = scene_from_json(json, path);
    capabilities_of(scene.render.engine, path);
    return json.dump();
}

/// The job of a render from Python: the scene's JSON with the overrides (KEY, JSON value) in
/// order, its AOVs and threads.
RenderJob python_job(const std::string& text, const std::string& path, const std::string& sha256,
                     const Overrides& overrides, const Keywords& keywords,
                     const std::vector<std::string>& aovs, int threads,
                     const std::vector<std::string>& command) {
    RenderJob job = make_job(with_overrides(text, path, overrides, keywords), path, sha256);
    job.run.command = command;
    job.options.threads = threads;
    for (const std::string& name : aovs) request_aov(job, name, path, "aovs");
    return job;
}

/// Renders with the GIL released. SIGINT (on the main thread) ends the pass in progress, as
/// on the command line, and then raises KeyboardInterrupt. `progress(fraction, spp, seconds)`
/// runs after each pass, with the GIL. `time` (None: none) is checked as --time is.
py::dict render(const std::string& text, const std::string& path, const std::string& sha256,
                const Overrides& overrides, const Keywords& keywords,
                const std::vector<std::string>& aovs, int threads, std::optional<double> time,
                const std::vector<std::string>& command, const py::object& progress) {
    RenderJob job = python_job(text, path, sha256, overrides, keywords, aovs, threads, command);
    if (time) set_time_budget(job, *time, path, "time");
    const double time_budget = job.options.time_budget;
    const int planned = job.scene.render.spp;
    if (!progress.is_none()) {
        job.options.on_pass = [&](int passes, double seconds, const Image&) {
            py::gil_scoped_acquire gil;
            const double fraction = time_budget > 0.0 ? std::min(1.0, seconds / time_budget)
                                                      : static_cast<double>(passes) / planned;
            progress(fraction, passes, seconds);
        };
    }
    const py::module_ threading = py::module_::import("threading");
    const bool main_thread = threading.attr("current_thread")().is(threading.attr("main_thread")());
    RenderResult result;
    int signal = 0;
    {
        std::optional<InterruptGuard> guard;
        if (main_thread) {
            guard.emplace();
            job.options.cancel = &guard->flag();
        }
        py::gil_scoped_release release;
        result = run_job(job);
        if (guard) signal = guard->signal();
    }
    if (signal == SIGTERM) std::raise(SIGTERM);  // the handler is Python's again
    if (signal != 0) {
        PyErr_SetNone(PyExc_KeyboardInterrupt);
        throw py::error_already_set();
    }
    const int spp = reached_spp(job, result);
    if (!progress.is_none() && result.stats.passes == 0) progress(1.0, spp, result.stats.seconds);

    // Each image is copied once and freed at once: the peak is the render's and one image.
    py::dict out;
    out["image"] = to_array(result.color);
    result.color = Image();
    py::dict images;
    while (!result.aovs.empty()) {
        auto first = result.aovs.begin();
        images[py::str(first->first)] = to_array(first->second);
        result.aovs.erase(first);
    }
    out["aovs"] = images;
    py::dict stats;
    stats["seconds"] = result.stats.seconds;
    stats["setup_seconds"] = result.stats.setup_seconds;
    stats["spp"] = spp;
    stats["rays"] = result.stats.rays;
    stats["nonfinite"] = result.stats.nonfinite;
    stats["engine"] = job.scene.render.engine;
    out["stats"] = stats;
    out["provenance"] = job_provenance(job, result);
    out["exposure"] = job.scene.render.exposure;
    return out;
}

/// For bench/python_overhead.py: the mean wall-clock seconds of the same render as `render`
/// (the job made from the JSON, then run), `repeats` times in C++ with no Python in the loop.
double native_render_seconds(const std::string& text, const std::string& path,
                             const std::string& sha256, const Overrides& overrides,
                             const Keywords& keywords, int threads, int repeats) {
    py::gil_scoped_release release;
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < repeats; ++k) {
        RenderJob job = python_job(text, path, sha256, overrides, keywords, {}, threads, {});
        RenderResult result = run_job(job);
        (void)job_provenance(job, result);
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
           std::max(repeats, 1);
}

/// svetlo trace's JSON of sample `sample` of pixel (x, y).
std::string trace(const std::string& text, const std::string& path, const std::string& sha256,
                  const Overrides& overrides, const Keywords& keywords, int x, int y,
                  long long sample, long long spp, int threads) {
    RenderJob job = python_job(text, path, sha256, overrides, keywords, {}, threads, {});
    PixelTrace log;
    {
        py::gil_scoped_release release;
        log = trace_job(job, x, y, sample, spp);
    }
    return trace_json(log, job.scene.render.engine).dump();
}

/// svetlo compare's --json of the techniques (SPECs) against the reference; with `html` or
/// `png`, the sheet is written there too.
std::string compare(const std::string& text, const std::string& path, const std::string& sha256,
                    const Overrides& overrides, const Keywords& keywords,
                    const std::vector<std::string>& techniques, const std::string& reference,
                    int threads, bool curves, const std::string& html, const std::string& png) {
    if (techniques.empty()) throw Error(path, "techniques", "give at least one technique SPEC");
    if (!png.empty()) check_writable(png, "png");
    if (!html.empty()) check_creatable(html, "html");
    const nlohmann::json json = with_overrides(text, path, overrides, keywords);
    Sheet sheet;
    {
        py::gil_scoped_release release;
        sheet =
            compare_techniques(json, path, sha256, techniques, reference, threads, curves, true);
    }
    if (!html.empty()) write_text_file(html, sheet_html(sheet), "html");
    if (!png.empty()) write_image(png, sheet_png(sheet), PixelMeaning::Radiance, 1.0f, "png");
    return sheet_json(sheet).dump();
}

/// The four metrics of `svetlo diff` (docs/metrics.md): LDR-ꟻLIP when `ldr`.
py::dict diff(const FloatArray& a, const FloatArray& b, bool ldr, int threads) {
    const Image test = from_array(a, "a"), reference = from_array(b, "b");
    if (test.width != reference.width || test.height != reference.height)
        throw py::value_error("a is " + std::to_string(test.width) + " x " +
                              std::to_string(test.height) + " but b is " +
                              std::to_string(reference.width) + " x " +
                              std::to_string(reference.height));
    ImageComparison c;
    {
        py::gil_scoped_release release;
        c = compare_images(test, reference, ldr, threads);
    }
    py::dict out;
    for (const char* metric : {"mae", "rmse", "relmse", "flip"}) out[metric] = c.value(metric);
    return out;
}

/// An image file as svetlo reads it: (H x W x 3 linear array, whether it was 8-bit sRGB).
py::tuple read_image_file(const std::string& path) {
    LoadedImage loaded = read_image(path, "image");
    return py::make_tuple(to_array(loaded.image), loaded.ldr);
}

/// The PNG bytes of a radiance image, as `render -o x.png` encodes it.
py::bytes png(const FloatArray& a, float exposure) {
    const std::vector<unsigned char> bytes =
        encode_png(from_array(a, "image"), PixelMeaning::Radiance, exposure, "");
    return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

/// The scene's triangles as the rasterizer tessellates them: world-space positions (N x 3
/// float32) and the vertex indices of each triangle (M x 3 uint32), counter-clockwise from its
/// front.
py::tuple triangles(const std::string& text, const std::string& path) {
    const Scene scene = scene_from_json(parse(text, path), path);
    const LightSet lights(scene);
    const std::vector<Object> copies = instance_copies(scene);
    const TriangleList list =
        build_triangle_list(object_pointers(scene.objects, copies, lights.area_light_quads()),
                            tessellation_options(scene.render), 0);
    py::array_t<float> positions({static_cast<py::ssize_t>(list.positions.size()), py::ssize_t{3}});
    std::memcpy(positions.mutable_data(), list.positions.data(),
                list.positions.size() * sizeof(vec3));
    py::array_t<uint32_t> indices(
        {static_cast<py::ssize_t>(list.indices.size() / 3), py::ssize_t{3}});
    std::memcpy(indices.mutable_data(), list.indices.data(),
                list.indices.size() * sizeof(uint32_t));
    return py::make_tuple(positions, indices);
}

}  // namespace

PYBIND11_MODULE(_svetlo, m) {
    m.doc() = "svetlo's compiled core; use the package `svetlo` (docs/python.md)";
    py::register_exception<Error>(m, "SceneError", PyExc_ValueError);
    m.def("read_scene",
          [](const std::string& path) { return effective_scene_json(path, {}).dump(); });
    m.def("sha256_file", [](const std::string& path) { return sha256_file(path); });
    m.def("sha256_text", [](const std::string& text) { return sha256_hex(text); });
    m.def("validate", &validate);
    m.def("set_key", &set_key);
    m.def("render", &render);
    m.def("trace", &trace);
    m.def("native_render_seconds", &native_render_seconds);
    m.def("diff", &diff);
    m.def("compare", &compare);
    m.def("read_image", &read_image_file);
    m.def("png", &png);
    m.def("triangles", &triangles);
    m.attr("aov_names") = aov_names();
    m.attr("debug_aov_names") = debug_aov_names();
    // The command line's bounds, so that the keywords are held to the same (svetlo/job/limits.h,
    // scene_loader.h).
    m.attr("max_threads") = kMaxThreads;
    m.attr("max_spp") = kMaxSpp;
}
