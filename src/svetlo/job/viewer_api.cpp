#include "svetlo/job/viewer_api.h"

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/image_metrics.h"
#include "svetlo/core/sha256.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/pixel_trace_job.h"
#include "svetlo/job/sheet.h"
#include "svetlo/scene/model_scene.h"

namespace svetlo {

namespace {

namespace fs = std::filesystem;

/// What one request may ask: the viewer's film and samples are bounded, so that no client
/// can hold the machine.
constexpr RequestLimits kRequestLimits{1920, 4096};

/// The frame drawn while the view moves (preview=1; docs/viewer.md, "While the view moves"):
/// the rasterizer draws each light with area from at most this many points, in its shading
/// (render.area_light_points) and its shadows (render.area_shadow_points): one, the light's
/// centre, a hard shadow while moving, as a real-time viewport's first sample of its soft
/// shadows. The still frame is the scene's.
constexpr int kPreviewAreaPoints = 1;

/// The environment maps /api/scenes lists at most (a folder of many images lists these).
constexpr size_t kMaxEnvironments = 200;

/// A progressive stream's frames while it refines: at most one each this long (the last,
/// lossless, always).
constexpr auto kFrameInterval = std::chrono::milliseconds(100);

/// A render in progress, counted while it lives.
class InProgress {
public:
    explicit InProgress(std::atomic<int>& count) : count_(count) { ++count_; }
    ~InProgress() { --count_; }
    InProgress(const InProgress&) = delete;
    InProgress& operator=(const InProgress&) = delete;

private:
    std::atomic<int>& count_;
};

ViewerResponse json_answer(const std::string& body) {
    return {200, "application/json", body, {{"Cache-Control", "no-store"}}};
}

/// The path of a request target, without its query.
std::string_view path_of(std::string_view target) {
    return target.substr(0, std::min(target.find('?'), target.find('#')));
}

}  // namespace

ViewerApi::ViewerApi(const std::string& target_text) {
    std::error_code ec;
    fs::path target = target_text.empty() ? fs::path(".") : fs::path(target_text);
    if (fs::is_regular_file(target)) {
        default_scene_ = target.filename().string();
        target = target.has_parent_path() ? target.parent_path() : fs::path(".");
    } else if (!fs::is_directory(target)) {
        throw Error(target_text, "serve", "is neither a scene file nor a folder");
    }
    folder_ = fs::canonical(target, ec);
    if (ec) throw Error(target_text, "serve", "cannot be read: " + ec.message());
    scope_ = FileScope(folder_);
}

/// The scene NAME of a request, a regular file directly in the folder (no path, no dot file,
/// no link out of it); throws Error naming `scene`.
fs::path ViewerApi::scene_path(const std::string& name) const {
    if (name.empty()) throw Error("svetlo serve", "scene", "no scene given");
    if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos ||
        name.front() == '.' || name.find('\0') != std::string::npos)
        throw Error(name, "scene", "is not a file of the scene folder");
    std::error_code ec;
    const fs::path path = fs::weakly_canonical(folder_ / name, ec);
    if (ec || path.parent_path() != folder_ || !fs::is_regular_file(path) ||
        !(path.extension() == ".json" || is_model_file(path)))
        throw Error(name, "scene", "is not a scene or model file of the scene folder");
    return path;
}

/// The request's job: the scene, then the engine, spp, film and --set overrides, checked as
/// the command line checks them. `b_side` makes the B side of an A/B comparison: the
/// engine of `b_engine` and the sets of `b_set` after the request's own.
RenderJob ViewerApi::request_job(const Query& req, bool b_side) {
    const fs::path path = scene_path(req.get("scene"));
    const std::string file = path.string();
    std::vector<std::string> sets = req.all("set");
    std::string engine = req.get("engine");
    if (b_side) {
        for (const std::string& s : req.all("b_set")) sets.push_back(s);
        if (req.has("b_engine")) engine = req.get("b_engine");
    }
    std::vector<Override> overrides = parse_sets(sets, file);
    add_key_overrides(file,
                      RequestKeys{engine, req.get("width"), req.get("height"), req.get("spp"), {}},
                      kKeywordNames, overrides, kRequestLimits);
    const std::string preview = req.get("preview");
    if (!preview.empty() && preview != "0" && preview != "1")
        throw Error(file, "preview", "must be 0 or 1, not '" + preview + "'");
    RenderJob job = make_job(effective_scene_json(path, overrides, &files_, scope_), path,
                             sha256_file(path), &files_, scope_);
    if (preview == "1") {
        RenderSettings& r = job.scene.render;
        r.area_light_points = std::min(r.area_light_points, kPreviewAreaPoints);
        r.area_shadow_points = std::min(r.area_shadow_points, kPreviewAreaPoints);
    }
    make_renderer(job.scene.render.engine, file);  // an unknown engine: one line
    job.options.accels = &accels_;
    job.options.triangle_lists = &triangle_lists_;
    job.options.occluder_cubes = &occluder_cubes_;
    if (check_) check_(job);
    return job;
}

/// The cancel flag of a client's new request; its request in progress, if any, is cancelled
/// (it ends after its pass). No client id: nothing to supersede.
std::shared_ptr<std::atomic<bool>> ViewerApi::supersede(const std::string& client) {
    auto cancel = std::make_shared<std::atomic<bool>>(false);
    if (client.empty()) return cancel;
    std::lock_guard lock(mutex_);
    auto& slot = current_[client];
    if (slot) slot->store(true);
    slot = cancel;
    return cancel;
}

/// An error answer: its one line, naming files relative to the served folder.
ViewerResponse ViewerApi::fail(int status, const std::string& message) const {
    return {status, "text/plain; charset=utf-8", scope_.relative_text(message) + "\n", {}};
}

ViewerResponse ViewerApi::get(std::string_view target, const std::atomic<bool>* cancel) {
    const std::string_view path = path_of(target);
    const Query req(target);
    try {
        if (path == "/api/scenes") return scenes();
        if (path == "/api/engines") return engines();
        if (path == "/api/scene") return scene(req);
        if (path == "/api/link") return link(req);
        if (path == "/api/render") return render(req, target, cancel);
        if (path == "/api/diff") return diff(req);
        if (path == "/api/trace") return trace(req);
        if (path == "/api/status")
            return json_answer(nlohmann::json{{"renders", renders_.load()}}.dump());
        return fail(404, "svetlo serve: " + std::string(path) + ": no such request");
    } catch (const Error& e) {
        return fail(400, e.what());
    } catch (const std::exception& e) {
        return fail(500, std::string("svetlo: internal: ") + e.what());
    }
}

/// /api/scenes: the folder's scene and model files, the one given, and the environment
/// maps in the folder or two folders down that this build reads (the page's menus).
ViewerResponse ViewerApi::scenes() {
    std::error_code ec;  // an unreadable entry is left out
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder_, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_regular_file() && name[0] != '.' &&
            (entry.path().extension() == ".json" || is_model_file(entry.path())))
            names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    std::vector<std::string> environments;
    fs::recursive_directory_iterator it(folder_, ec), end;
    for (; !ec && it != end && environments.size() < kMaxEnvironments; it.increment(ec)) {
        if (it.depth() >= 2) it.disable_recursion_pending();
        const fs::path& p = it->path();
        const std::string ext = lower_extension(p);
        if (it->is_regular_file() && p.filename().string()[0] != '.' &&
            (ext == ".hdr" || ext == ".pfm" || (ext == ".exr" && reads_exr())))
            environments.push_back(p.lexically_relative(folder_).generic_string());
    }
    std::sort(environments.begin(), environments.end());
    return json_answer(nlohmann::json{
        {"scenes", names}, {"default", default_scene_}, {"environments", environments}}
                           .dump());
}

/// /api/engines: the engines and what each can do, from the registry (job/engines.h): the
/// page builds its menus from it and streams the passes of an engine that shows them.
ViewerResponse ViewerApi::engines() {
    nlohmann::json list = nlohmann::json::array();
    for (const Capabilities& c : engine_capabilities())
        list.push_back({{"name", c.name},
                        {"progressive", c.progressive},
                        {"shows_passes", c.shows_passes},
                        {"debug_aovs", c.debug_aovs}});
    return json_answer(list.dump());
}

/// /api/scene: a scene's effective JSON (the page orbits its camera).
ViewerResponse ViewerApi::scene(const Query& req) {
    const fs::path path = scene_path(req.get("scene"));
    return json_answer(effective_scene_json(path, {}, &files_, scope_).dump());
}

/// /api/link: a shared link as the page starts from it (docs/viewer.md, "Links"): its values
/// read as a request's are, each set= and b_set= value as --set reads it (override_value: the
/// page never reads one itself), and in "error" the first problem found, one line: a scene
/// that is not in the folder, an unknown engine, a samples count out of range, a set= without
/// KEY=VALUE. What could be read is returned all the same.
ViewerResponse ViewerApi::link(const Query& link) {
    nlohmann::json out = nlohmann::json::object();
    std::string error;
    auto check = [&](const auto& read) {
        try {
            read();
        } catch (const Error& e) {
            if (error.empty()) error = scope_.relative_text(e.what());
        }
    };
    const std::string scene = link.has("scene") ? link.get("scene") : default_scene_;
    const std::string file = scene.empty() ? "link" : scene;
    out["scene"] = scene;
    if (link.has("scene")) check([&] { scene_path(scene); });
    for (const char* name : {"engine", "b_engine"}) {
        out[name] = link.get(name);
        if (!link.get(name).empty()) check([&] { capabilities_of(link.get(name), file); });
    }
    if (link.has("spp"))
        check([&] {
            out["spp"] = flag_integer(file, "spp", link.get("spp"), 1, kRequestLimits.spp);
        });
    for (const char* name : {"aov", "ab"}) out[name] = link.get(name);
    for (const char* name : {"set", "b_set"}) {
        nlohmann::json& list = out[std::string(name) + "s"] = nlohmann::json::array();
        for (const std::string& text : link.all(name)) {
            check([&] {
                const Override o = parse_sets({text}, file).front();
                list.push_back(
                    {{"key", o.key}, {"value", override_value(o.value)}, {"text", text}});
            });
        }
    }
    if (!error.empty()) out["error"] = error;
    return json_answer(out.dump());
}

/// /api/render: one render's image, or the AOV that aov= names: a PNG with its provenance
/// when the view is still, a JPEG while it moves (format=jpeg).
ViewerResponse ViewerApi::render(const Query& req, std::string_view target,
                                 const std::atomic<bool>* cancel) {
    RenderJob job = request_job(req);
    // aov=NAME: that buffer instead of the image, drawn as its PNG would be.
    const std::string aov = req.get("aov");
    if (!aov.empty()) request_aov(job, aov, job.run.scene_file.string(), "aov");
    // This client's newer request supersedes the one in progress: it is cancelled.
    const auto superseded = supersede(req.get("client"));
    job.options.cancel = cancel != nullptr ? cancel : superseded.get();
    InProgress busy(renders_);
    const RenderResult result = run_job(job, renderers_);
    if (superseded->load()) return fail(409, "superseded by a newer request");
    // JPEG while the view moves (fast), PNG when it is still (lossless).
    const bool jpeg = req.get("format") == "jpeg";
    const auto t0 = std::chrono::steady_clock::now();
    Image buffer;
    if (!aov.empty()) buffer = aov_for_display(aov, result.aovs.at(aov));
    const Image& shown = aov.empty() ? result.color : buffer;
    const PixelMeaning meaning =
        aov.empty() || aov == "albedo" ? PixelMeaning::Radiance : PixelMeaning::Data;
    const float exposure = aov.empty() ? job.scene.render.exposure : 1.0f;
    // A still image carries its provenance, as every file svetlo writes does.
    job.run.command = {"svetlo serve", std::string(target)};
    const std::vector<unsigned char> bytes =
        jpeg ? encode_jpeg(shown, meaning, exposure, 90)
             : encode_png(shown, meaning, exposure,
                          job_provenance(job, result, aov.empty() ? "color" : aov));
    const double encode =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return {200,
            jpeg ? "image/jpeg" : "image/png",
            std::string(bytes.begin(), bytes.end()),
            {{"X-Svetlo-Seconds", std::to_string(result.stats.seconds)},
             {"X-Svetlo-Encode-Seconds", std::to_string(encode)},
             {"X-Svetlo-Spp", std::to_string(reached_spp(job, result))},
             {"X-Svetlo-Technique", technique_name(job.scene.render)},
             {"Cache-Control", "no-store"}}};
}

/// /api/diff, A/B: both sides rendered (one after the other, sharing the caches), their
/// metrics as svetlo diff gives them (B against A), and the images and ꟻLIP's error map
/// inline.
ViewerResponse ViewerApi::diff(const Query& req) {
    RenderJob a = request_job(req), b = request_job(req, true);
    if (a.scene.film.width != b.scene.film.width || a.scene.film.height != b.scene.film.height)
        throw Error(a.run.scene_file.string(), "b_set", "B's film differs from A's");
    InProgress busy(renders_);
    const RenderResult ra = run_job(a, renderers_), rb = run_job(b, renderers_);
    const ImageComparison c = compare_images(rb.color, ra.color, false, a.options.threads);
    nlohmann::ordered_json j = {
        {"mae", c.pixels.mae},
        {"rmse", c.pixels.rmse},
        {"relmse", c.pixels.relmse},
        {"flip", c.flip.mean},
        {"seconds", {ra.stats.seconds, rb.stats.seconds}},
        {"a", png_data_url(ra.color, PixelMeaning::Radiance, a.scene.render.exposure)},
        {"b", png_data_url(rb.color, PixelMeaning::Radiance, b.scene.render.exposure)},
        {"error", png_data_url(false_color(c.flip.error, ra.color.width, ra.color.height, 1.0f),
                               PixelMeaning::Data, 1.0f)}};
    return json_answer(j.dump());
}

/// /api/trace: svetlo trace's JSON of one pixel (x=, y=).
ViewerResponse ViewerApi::trace(const Query& req) {
    RenderJob job = request_job(req);
    const std::string file = job.run.scene_file.string();
    const auto x = flag_integer(file, "x", req.get("x"), 0, kRequestLimits.side);
    const auto y = flag_integer(file, "y", req.get("y"), 0, kRequestLimits.side);
    InProgress busy(renders_);
    const PixelTrace log = trace_job(job, static_cast<int>(x), static_cast<int>(y), 0, 1);
    return json_answer(trace_json(log, job.scene.render.engine).dump());
}

ProgressiveRender ViewerApi::start_progressive(std::string_view target,
                                               const std::atomic<bool>* cancel) {
    const Query req(target);
    ProgressiveRender out;
    try {
        out.job = std::make_shared<RenderJob>(request_job(req));
        out.cancel = supersede(req.get("client"));
        out.job->options.cancel = cancel != nullptr ? cancel : out.cancel.get();
    } catch (const Error& e) {
        out.job.reset();
        out.failed = fail(400, e.what());
    }
    return out;
}

/// The stream (docs/viewer.md, "Progressive display"): frames, each a 4-byte big-endian
/// length, a JSON header {"spp", "seconds", "technique", "final", "type"}, a 4-byte length
/// and the image: a JPEG at most every 100 ms while it refines, a PNG at the end; or a
/// header {"error"} alone. A reader gone, or a newer request of the same client, ends it
/// after its pass.
void ViewerApi::run_progressive(ProgressiveRender& render,
                                const std::function<bool(std::string_view)>& write_bytes) {
    if (!render.job) return;
    RenderJob& job = *render.job;
    std::atomic<bool>& cancel = *render.cancel;
    InProgress busy(renders_);
    using Clock = std::chrono::steady_clock;
    auto last = Clock::now() - std::chrono::seconds(1);
    auto write = [&](const std::string& bytes) {
        const auto n = static_cast<uint32_t>(bytes.size());
        const char length[4] = {static_cast<char>(n >> 24), static_cast<char>(n >> 16),
                                static_cast<char>(n >> 8), static_cast<char>(n)};
        if (!write_bytes(std::string_view(length, 4)) || !write_bytes(bytes)) cancel.store(true);
    };
    auto send = [&](int spp, double seconds, const Image& image, bool final) {
        if (cancel.load() || job.options.cancel->load()) return;  // no one reads it
        const float exposure = job.scene.render.exposure;
        const std::vector<unsigned char> bytes =
            final ? encode_png(image, PixelMeaning::Radiance, exposure)
                  : encode_jpeg(image, PixelMeaning::Radiance, exposure, 90);
        write(nlohmann::json{{"spp", spp},
                             {"seconds", seconds},
                             {"technique", technique_name(job.scene.render)},
                             {"final", final},
                             {"type", final ? "image/png" : "image/jpeg"}}
                  .dump());
        write(std::string(bytes.begin(), bytes.end()));
    };
    job.options.on_pass = [&](int passes, double seconds, const Image& image) {
        if (Clock::now() - last < kFrameInterval) return;
        last = Clock::now();
        send(passes, seconds, image, false);
    };
    try {
        const RenderResult result = run_job(job, renderers_);
        send(reached_spp(job, result), result.stats.seconds, result.color, true);
    } catch (const std::exception& e) {
        write(nlohmann::json{{"error", scope_.relative_text(e.what())}}.dump());
    }
}

}  // namespace svetlo
