// svetlo serve [SCENE.json|DIR] [--port P] [--host H]: a live browser viewer (docs/viewer.md).
// It serves one page (viewer/index.html, inside the binary) and a small API that renders
// through the command line's own code:
//   GET /api/scenes                  the scene and model files of the folder, the one given, and
//                                    the environment maps in it
//   GET /api/engines                 the engines and their capabilities (the page's menus)
//   GET /api/scene?scene=NAME        a scene's effective JSON (the page orbits its camera)
//   GET /api/link?QUERY              a shared link read as the server reads a request: its
//                                    scene, engine and each set= value as --set reads it, and
//                                    the first problem found (the page starts from this)
//   GET /api/render?scene=NAME&engine=E&spp=N&width=W&height=H&set=KEY=VALUE...&client=ID
//                   [&format=jpeg][&preview=1]
//                                    a PNG with its provenance; X-Svetlo-Seconds and
//                                    X-Svetlo-Spp say how it went
//   GET /api/trace?...&x=X&y=Y      svetlo trace's JSON of that pixel
// A bad value gets HTTP 400 and the one-line message; a render superseded by a newer request
// of the same page is cancelled after its pass and answered 409. Only files directly in the
// scene folder are read as scenes; every file a scene names (from the file or from a set=
// override) must lie inside the folder (FileScope), and the messages a client sees name files
// relative to it. Query strings are read by Query: set=KEY=VALUE keeps its value whole.
#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "commands.h"
#include "query.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/image_metrics.h"
#include "svetlo/core/sha256.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/geometry/triangle_list_cache.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/interrupt.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/pixel_trace_job.h"
#include "svetlo/job/render_job.h"
#include "svetlo/job/sheet.h"
#include "svetlo/scene/model_scene.h"

namespace svetlo {

const char* viewer_page();  // viewer_page.cpp, generated

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

/// The server's threads: each client's work is one render at a time, and renders share the
/// cores.
constexpr size_t kThreads = 4;
/// The environment maps /api/scenes lists at most (a folder of many images lists these).
constexpr size_t kMaxEnvironments = 200;

struct Server {
    fs::path folder;  // canonical
    FileScope scope;  // the folder: every file a scene names lies in it
    std::string default_scene;
    std::mutex mutex;                                                   // guards `current`
    std::map<std::string, std::shared_ptr<std::atomic<bool>>> current;  // per client: its render
    FileCache meshes;                  // each mesh file and image read once (again when it changes)
    AccelCache accels;                 // a slider that moves no shape reuses the scene's BVH
    TriangleListCache triangle_lists;  // and the rasterizer's triangles
    OccluderCubeCache occluder_cubes;  // and its shadow rays' occluders
    RendererPool renderers{kThreads};  // a drag's frames draw into the last one's buffers
    std::atomic<int> renders{0};       // in progress (/api/status)
};

/// A render in progress, counted in Server::renders while it lives.
class InProgress {
public:
    explicit InProgress(std::atomic<int>& count) : count_(count) { ++count_; }
    ~InProgress() { --count_; }
    InProgress(const InProgress&) = delete;
    InProgress& operator=(const InProgress&) = delete;

private:
    std::atomic<int>& count_;
};

/// The scene NAME of a request, a regular file directly in the folder (no path, no dot file,
/// no link out of it); throws Error naming `scene`.
fs::path scene_path(const Server& server, const std::string& name) {
    if (name.empty()) throw Error("svetlo serve", "scene", "no scene given");
    if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos ||
        name.front() == '.' || name.find('\0') != std::string::npos)
        throw Error(name, "scene", "is not a file of the scene folder");
    std::error_code ec;
    const fs::path path = fs::weakly_canonical(server.folder / name, ec);
    if (ec || path.parent_path() != server.folder || !fs::is_regular_file(path) ||
        !(path.extension() == ".json" || is_model_file(path)))
        throw Error(name, "scene", "is not a scene or model file of the scene folder");
    return path;
}

/// The request's job: the scene, then the engine, spp, film and --set overrides, checked as
/// the command line checks them. `side` "b" makes the B side of an A/B comparison: the
/// engine of `b_engine` and the sets of `b_set` after the request's own.
RenderJob request_job(Server& server, const Query& req, const std::string& side = "") {
    const fs::path path = scene_path(server, req.get("scene"));
    const std::string file = path.string();
    std::vector<std::string> sets = req.all("set");
    std::string engine = req.get("engine");
    if (side == "b") {
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
    RenderJob job = make_job(effective_scene_json(path, overrides, &server.meshes, server.scope),
                             path, sha256_file(path), &server.meshes, server.scope);
    if (preview == "1") {
        RenderSettings& r = job.scene.render;
        r.area_light_points = std::min(r.area_light_points, kPreviewAreaPoints);
        r.area_shadow_points = std::min(r.area_shadow_points, kPreviewAreaPoints);
    }
    make_renderer(job.scene.render.engine, file);  // an unknown engine: one line
    job.options.accels = &server.accels;
    job.options.triangle_lists = &server.triangle_lists;
    job.options.occluder_cubes = &server.occluder_cubes;
    return job;
}

/// The cancel flag of a client's new request; its request in progress, if any, is cancelled
/// (it ends after its pass). No client id: nothing to supersede.
std::shared_ptr<std::atomic<bool>> supersede(Server& server, const std::string& client) {
    auto cancel = std::make_shared<std::atomic<bool>>(false);
    if (client.empty()) return cancel;
    std::lock_guard lock(server.mutex);
    auto& slot = server.current[client];
    if (slot) slot->store(true);
    slot = cancel;
    return cancel;
}

/// A progressive render's frames as its passes come (docs/viewer.md, "Progressive display"):
/// each a 4-byte big-endian length, a JSON header {"spp", "seconds", "final", "type"}, a
/// 4-byte length and the image: a JPEG at most every 100 ms while it refines, a PNG at the
/// end. A client gone, or a newer request of the same client, ends it after its pass.
void stream_passes(RenderJob& job, RendererPool& renderers, const FileScope& scope,
                   std::atomic<bool>& cancel, httplib::DataSink& sink) {
    using Clock = std::chrono::steady_clock;
    auto last = Clock::now() - std::chrono::seconds(1);
    auto write = [&](const std::string& bytes) {
        const auto n = static_cast<uint32_t>(bytes.size());
        const char length[4] = {static_cast<char>(n >> 24), static_cast<char>(n >> 16),
                                static_cast<char>(n >> 8), static_cast<char>(n)};
        if (!sink.is_writable() || !sink.write(length, 4) || !sink.write(bytes.data(), n))
            cancel.store(true);
    };
    auto send = [&](int spp, double seconds, const Image& image, bool final) {
        if (cancel.load()) return;
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
        if (Clock::now() - last < std::chrono::milliseconds(100)) return;
        last = Clock::now();
        send(passes, seconds, image, false);
    };
    try {
        const RenderResult result = run_job(job, renderers);
        send(reached_spp(job, result), result.stats.seconds, result.color, true);
    } catch (const std::exception& e) {
        write(nlohmann::json{{"error", scope.relative_text(e.what())}}.dump());
    }
}

/// A shared link as the page starts from it (docs/viewer.md, "Links"): its values read as a
/// request's are, each set= and b_set= value as --set reads it (override_value: the page
/// never reads one itself), and in "error" the first problem found, one line: a scene that is
/// not in the folder, an unknown engine, a samples count out of range, a set= without
/// KEY=VALUE. What could be read is returned all the same.
nlohmann::json read_link(const Server& server, const Query& link) {
    nlohmann::json out = nlohmann::json::object();
    std::string error;
    auto check = [&](const auto& read) {
        try {
            read();
        } catch (const Error& e) {
            if (error.empty()) error = server.scope.relative_text(e.what());
        }
    };
    const std::string scene = link.has("scene") ? link.get("scene") : server.default_scene;
    const std::string file = scene.empty() ? "link" : scene;
    out["scene"] = scene;
    if (link.has("scene")) check([&] { scene_path(server, scene); });
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
    return out;
}

/// An error answer: its one line, naming files relative to the served folder.
void fail(const Server& server, httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(server.scope.relative_text(message) + "\n", "text/plain; charset=utf-8");
}

/// GET /api/scenes: the folder's scene and model files, the one given, and the environment
/// maps in the folder or two folders down (the page's menus).
void serve_scenes(Server& server, const httplib::Request&, httplib::Response& res) {
    std::error_code ec;  // an unreadable entry is left out
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(server.folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_regular_file() && name[0] != '.' &&
            (entry.path().extension() == ".json" || is_model_file(entry.path())))
            names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    // The environment maps the folder holds (.hdr, .exr, .pfm, in it or two folders
    // down), relative to it: the viewer's environment menu.
    std::vector<std::string> environments;
    fs::recursive_directory_iterator it(server.folder, ec), end;
    for (; !ec && it != end && environments.size() < kMaxEnvironments; it.increment(ec)) {
        if (it.depth() >= 2) it.disable_recursion_pending();
        const fs::path& p = it->path();
        const std::string ext = lower_extension(p);
        if (it->is_regular_file() && p.filename().string()[0] != '.' &&
            (ext == ".hdr" || ext == ".exr" || ext == ".pfm"))
            environments.push_back(p.lexically_relative(server.folder).generic_string());
    }
    std::sort(environments.begin(), environments.end());
    res.set_content(
        nlohmann::json{
            {"scenes", names}, {"default", server.default_scene}, {"environments", environments}}
            .dump(),
        "application/json");
}

/// GET /api/scene: a scene's effective JSON (the page orbits its camera).
void serve_scene(Server& server, const httplib::Request& request, httplib::Response& res) {
    const Query req(request.target);
    try {
        const fs::path path = scene_path(server, req.get("scene"));
        res.set_content(effective_scene_json(path, {}, &server.meshes, server.scope).dump(),
                        "application/json");
    } catch (const Error& e) {
        fail(server, res, 400, e.what());
    }
}

/// GET /api/render: one render's image, or the AOV that aov= names: a PNG with its provenance
/// when the view is still, a JPEG while it moves (format=jpeg).
void serve_render(Server& server, const httplib::Request& request, httplib::Response& res) {
    const Query req(request.target);
    try {
        RenderJob job = request_job(server, req);
        // aov=NAME: that buffer instead of the image, drawn as its PNG would be.
        const std::string aov = req.get("aov");
        if (!aov.empty()) request_aov(job, aov, job.run.scene_file.string(), "aov");
        // This client's newer request supersedes the one in progress: it is cancelled.
        auto cancel = supersede(server, req.get("client"));
        job.options.cancel = cancel.get();
        InProgress busy(server.renders);
        const RenderResult result = run_job(job, server.renderers);
        if (cancel->load()) return fail(server, res, 409, "superseded by a newer request");
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
        job.run.command = {"svetlo serve", request.target};
        const std::vector<unsigned char> bytes =
            jpeg ? encode_jpeg(shown, meaning, exposure, 90)
                 : encode_png(shown, meaning, exposure,
                              job_provenance(job, result, aov.empty() ? "color" : aov));
        const double encode =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        res.set_header("X-Svetlo-Seconds", std::to_string(result.stats.seconds));
        res.set_header("X-Svetlo-Encode-Seconds", std::to_string(encode));
        res.set_header("X-Svetlo-Spp", std::to_string(reached_spp(job, result)));
        res.set_header("X-Svetlo-Technique", technique_name(job.scene.render));
        res.set_header("Cache-Control", "no-store");
        res.set_content(std::string(bytes.begin(), bytes.end()), jpeg ? "image/jpeg" : "image/png");
    } catch (const Error& e) {
        fail(server, res, 400, e.what());
    } catch (const std::exception& e) {
        fail(server, res, 500, std::string("svetlo: internal: ") + e.what());
    }
}

/// GET /api/progressive: the same render, its passes streamed as they come (an engine that
/// shows its passes: path, radiosity's solver).
void serve_progressive(Server& server, const httplib::Request& request, httplib::Response& res) {
    const Query req(request.target);
    try {
        auto job = std::make_shared<RenderJob>(request_job(server, req));
        auto cancel = supersede(server, req.get("client"));
        job->options.cancel = cancel.get();
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "application/octet-stream", [job, cancel, &server](size_t, httplib::DataSink& sink) {
                InProgress busy(server.renders);
                stream_passes(*job, server.renderers, server.scope, *cancel, sink);
                sink.done();
                return true;
            });
    } catch (const Error& e) {
        fail(server, res, 400, e.what());
    }
}

/// GET /api/diff, A/B: both sides rendered (one after the other, sharing the caches), their metrics
/// as svetlo diff gives them (B against A), and the images and ꟻLIP's error map inline.
void serve_diff(Server& server, const httplib::Request& request, httplib::Response& res) {
    const Query req(request.target);
    try {
        RenderJob a = request_job(server, req), b = request_job(server, req, "b");
        if (a.scene.film.width != b.scene.film.width || a.scene.film.height != b.scene.film.height)
            throw Error(a.run.scene_file.string(), "b_set", "B's film differs from A's");
        InProgress busy(server.renders);
        const RenderResult ra = run_job(a, server.renderers), rb = run_job(b, server.renderers);
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
        res.set_header("Cache-Control", "no-store");
        res.set_content(j.dump(), "application/json");
    } catch (const Error& e) {
        fail(server, res, 400, e.what());
    }
}

/// GET /api/trace: svetlo trace's JSON of one pixel (x=, y=).
void serve_trace(Server& server, const httplib::Request& request, httplib::Response& res) {
    const Query req(request.target);
    try {
        RenderJob job = request_job(server, req);
        const std::string file = job.run.scene_file.string();
        const auto x = flag_integer(file, "x", req.get("x"), 0, kRequestLimits.side);
        const auto y = flag_integer(file, "y", req.get("y"), 0, kRequestLimits.side);
        InProgress busy(server.renders);
        const PixelTrace log = trace_job(job, static_cast<int>(x), static_cast<int>(y), 0, 1);
        res.set_content(trace_json(log, job.scene.render.engine).dump(), "application/json");
    } catch (const Error& e) {
        fail(server, res, 400, e.what());
    }
}

/// The folder a server serves, from `target` (a folder, or a scene file in it: the default).
void open_folder(Server& server, const std::string& target_text) {
    std::error_code ec;
    fs::path target = target_text.empty() ? fs::path(".") : fs::path(target_text);
    if (fs::is_regular_file(target)) {
        server.default_scene = target.filename().string();
        target = target.has_parent_path() ? target.parent_path() : fs::path(".");
    } else if (!fs::is_directory(target)) {
        throw Error(target_text, "serve", "is neither a scene file nor a folder");
    }
    server.folder = fs::canonical(target, ec);
    if (ec) throw Error(target_text, "serve", "cannot be read: " + ec.message());
    server.scope = FileScope(server.folder);
}

/// GET /api/engines: the engines and what each can do, from the registry (job/engines.h):
/// the page builds its menus from it and streams the passes of an engine that shows them.
void serve_engines(Server&, const httplib::Request&, httplib::Response& res) {
    nlohmann::json list = nlohmann::json::array();
    for (const Capabilities& c : engine_capabilities())
        list.push_back({{"name", c.name},
                        {"progressive", c.progressive},
                        {"shows_passes", c.shows_passes},
                        {"debug_aovs", c.debug_aovs}});
    res.set_content(list.dump(), "application/json");
}

/// GET /api/link: a shared link read as a request is (read_link).
void serve_link(Server& server, const httplib::Request& request, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(read_link(server, Query(request.target)).dump(), "application/json");
}

/// GET /api/status: the renders in progress.
void serve_status(Server& server, const httplib::Request&, httplib::Response& res) {
    res.set_content(nlohmann::json{{"renders", server.renders.load()}}.dump(), "application/json");
}

}  // namespace
int run_serve(const ServeArgs& args) {
    Server server;
    open_folder(server, args.target);
    const long long port =
        flag_integer(args.target, "--port", args.port.empty() ? "8080" : args.port, 0, 65535);
    const std::string host = args.host.empty() ? "127.0.0.1" : args.host;

    httplib::Server http;
    // SO_REUSEADDR only: cpp-httplib also sets SO_REUSEPORT, with which a second server would
    // share a port in use instead of being refused.
    http.set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    // No Nagle: a response goes out as headers, then body, and on a kept-alive connection
    // (the browser's) the body waited for the client's delayed acknowledgement of the headers,
    // a few milliseconds a frame (the drag: 23 -> 27 frames a second, bench/serve_latency.py).
    http.set_tcp_nodelay(true);
    http.new_task_queue = [] { return new httplib::ThreadPool(kThreads); };
    using Handler = void (*)(Server&, const httplib::Request&, httplib::Response&);
    const std::pair<const char*, Handler> routes[] = {{"/api/scenes", serve_scenes},
                                                      {"/api/engines", serve_engines},
                                                      {"/api/scene", serve_scene},
                                                      {"/api/link", serve_link},
                                                      {"/api/render", serve_render},
                                                      {"/api/status", serve_status},
                                                      {"/api/progressive", serve_progressive},
                                                      {"/api/diff", serve_diff},
                                                      {"/api/trace", serve_trace}};
    http.Get("/", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(viewer_page(), "text/html; charset=utf-8");
    });
    for (const auto& [path, handler] : routes)
        http.Get(path,
                 [&server, handler = handler](const httplib::Request& q, httplib::Response& r) {
                     handler(server, q, r);
                 });

    const int bound =
        port == 0 ? http.bind_to_any_port(host)
                  : (http.bind_to_port(host, static_cast<int>(port)) ? static_cast<int>(port) : -1);
    if (bound < 0)
        throw Error(host + ":" + std::to_string(port), "--port", "cannot listen there (in use?)");
    if (host != "127.0.0.1" && host != "localhost" && host != "::1") {
        std::fprintf(stderr,
                     "svetlo: warning: serving on %s: every machine that reaches it can render "
                     "(and read the scenes of %s)\n",
                     host.c_str(), server.folder.c_str());
    }
    std::fprintf(stderr, "svetlo: serving http://%s:%d/\n", host.c_str(), bound);
    std::fflush(stderr);
    // SIGINT or SIGTERM stops the server (exit 0).
    InterruptGuard interrupt;
    std::thread listener([&] { http.listen_after_bind(); });
    while (!interrupt.flag().load()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    http.stop();
    listener.join();
    return 0;
}

}  // namespace svetlo
