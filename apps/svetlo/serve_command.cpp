// svetlo serve [SCENE.json|DIR] [--port P] [--host H]: a live browser viewer (docs/viewer.md).
// It serves the viewer's page (viewer/: index.html, viewer.js and backend.js, inside the
// binary; the web page shares them) and answers its requests with the job layer's ViewerApi
// (job/viewer_api.h), which the web page's module answers them with too: this file only
// carries them over HTTP.
#include <httplib.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string_view>
#include <thread>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/job/interrupt.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/viewer_api.h"

namespace svetlo {

/// The viewer's file NAME ("index.html", "viewer.js", "backend.js"), or nullptr
/// (viewer_files.cpp, generated).
const char* viewer_file(std::string_view name);

namespace {

/// The server's threads: each client's work is one render at a time, and renders share the
/// cores.
constexpr size_t kThreads = 4;

void answer(httplib::Response& res, const ViewerResponse& r) {
    res.status = r.status;
    for (const auto& [name, value] : r.headers) res.set_header(name, value);
    res.set_content(r.body, r.type);
}

/// GET /api/progressive: the render's passes streamed as they come (ViewerApi::run_progressive).
void serve_progressive(ViewerApi& api, const httplib::Request& request, httplib::Response& res) {
    auto render = std::make_shared<ProgressiveRender>(api.start_progressive(request.target));
    if (!render->job) return answer(res, render->failed);
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider(
        "application/octet-stream", [render, &api](size_t, httplib::DataSink& sink) {
            api.run_progressive(*render, [&sink](std::string_view bytes) {
                return sink.is_writable() && sink.write(bytes.data(), bytes.size());
            });
            sink.done();
            return true;
        });
}

/// The page's own files: "/" is index.html.
void serve_file(const httplib::Request& request, httplib::Response& res) {
    const std::string name = request.path == "/" ? "index.html" : request.path.substr(1);
    const char* text = viewer_file(name);
    if (text == nullptr) {
        res.status = 404;
        return res.set_content(name + ": not a file of the viewer\n", "text/plain; charset=utf-8");
    }
    const bool html = name.size() > 5 && name.substr(name.size() - 5) == ".html";
    res.set_content(text, html ? "text/html; charset=utf-8" : "text/javascript; charset=utf-8");
}

}  // namespace

int run_serve(const ServeArgs& args) {
    ViewerApi api(args.target);
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
    http.Get("/api/progressive", [&api](const httplib::Request& q, httplib::Response& r) {
        serve_progressive(api, q, r);
    });
    http.Get("/api/.*", [&api](const httplib::Request& q, httplib::Response& r) {
        answer(r, api.get(q.target));
    });
    http.Get("/|/[a-z_]+\\.(html|js)", serve_file);

    const int bound =
        port == 0 ? http.bind_to_any_port(host)
                  : (http.bind_to_port(host, static_cast<int>(port)) ? static_cast<int>(port) : -1);
    if (bound < 0)
        throw Error(host + ":" + std::to_string(port), "--port", "cannot listen there (in use?)");
    if (host != "127.0.0.1" && host != "localhost" && host != "::1") {
        std::fprintf(stderr,
                     "svetlo: warning: serving on %s: every machine that reaches it can render "
                     "(and read the scenes of %s)\n",
                     host.c_str(), api.folder().c_str());
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
