// The viewer's requests (docs/viewer.md, "The API"), answered by one piece of code whoever
// carries them: `svetlo serve` over HTTP, the web page through its worker (docs/web.md). A
// request is a target as a browser writes it ("/api/render?scene=cornell.json&engine=raster&
// set=render.shading=phong"); the answer is a status, a content type, headers and a body:
//   /api/scenes                  the scene and model files of the folder, the default one,
//                                and the environment maps in it (two folders down) that
//                                this build reads
//   /api/engines                 the engines and their capabilities (the page's menus)
//   /api/scene?scene=NAME        a scene's effective JSON (the page orbits its camera)
//   /api/link?QUERY              a shared link read as a request is: its scene, engine and
//                                each set= value as --set reads it, and the first problem found
//   /api/render?scene=NAME&engine=E&spp=N&width=W&height=H&set=KEY=VALUE...&client=ID
//               [&aov=NAME][&format=jpeg][&preview=1]
//                                a PNG with its provenance (a JPEG with format=jpeg);
//                                X-Svetlo-Seconds, -Spp, -Technique say how it went
//   /api/progressive?...         the same render's passes as they come (start_progressive)
//   /api/diff?...&ab=..&b_engine=E&b_set=...   A and B, their metrics and ꟻLIP's error map
//   /api/trace?...&x=X&y=Y      svetlo trace's JSON of that pixel
//   /api/status                  the renders in progress
// A bad value gets status 400 and the one-line message, naming files relative to the
// folder; a render superseded by a newer request of the same client ends after its pass and
// is answered 409. Only files directly in the folder are scenes, and every file a scene names
// must lie inside it (FileScope).
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "svetlo/core/file_scope.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/geometry/triangle_list_cache.h"
#include "svetlo/job/query.h"
#include "svetlo/job/render_job.h"
#include "svetlo/job/renderer_pool.h"
#include "svetlo/scene/file_cache.h"

namespace svetlo {

struct ViewerResponse {
    int status = 200;
    std::string type;  // the content type
    std::string body;
    std::vector<std::pair<std::string, std::string>> headers;
};

/// A progressive render read from its request (ViewerApi::start_progressive): `failed` holds
/// the answer to a bad request (status 400); else ViewerApi::run_progressive renders it.
struct ProgressiveRender {
    ViewerResponse failed;
    std::shared_ptr<RenderJob> job;
    std::shared_ptr<std::atomic<bool>> cancel;  // set: ends after its pass
};

class ViewerApi {
public:
    /// The renders of one request share the machine's cores; at most this many renderers
    /// keep their buffers between requests.
    static constexpr size_t kRenderers = 4;

    /// Serves `target`, a folder or a scene file in it (then the default scene); throws Error.
    explicit ViewerApi(const std::string& target);

    /// Checks each job before it renders (the web page refuses a film past its memory with
    /// the one-line error); throws Error.
    void set_job_check(std::function<void(const RenderJob&)> check) { check_ = std::move(check); }

    const std::filesystem::path& folder() const { return folder_; }

    /// The answer to `target`, any route but /api/progressive (404 for a path it does not
    /// know). `cancel`, when given, is the render's flag in place of the client's (the page's
    /// worker sets it from the page).
    ViewerResponse get(std::string_view target, const std::atomic<bool>* cancel = nullptr);

    /// /api/progressive in two steps, so that a bad request is answered before the stream
    /// starts: the request read, then `run_progressive` hands the stream's bytes to `write` as
    /// they come (docs/viewer.md, "Progressive display"); `write` returning false (the reader
    /// is gone) ends the render after its pass, unless an outer flag was given, which alone
    /// then ends it (the web page's worker, whose writes do not fail).
    ProgressiveRender start_progressive(std::string_view target,
                                        const std::atomic<bool>* cancel = nullptr);
    void run_progressive(ProgressiveRender& render,
                         const std::function<bool(std::string_view)>& write);

private:
    std::filesystem::path scene_path(const std::string& name) const;
    RenderJob request_job(const Query& req, bool b_side = false);
    std::shared_ptr<std::atomic<bool>> supersede(const std::string& client);
    ViewerResponse fail(int status, const std::string& message) const;

    ViewerResponse scenes();
    ViewerResponse engines();
    ViewerResponse scene(const Query& req);
    ViewerResponse link(const Query& req);
    ViewerResponse render(const Query& req, std::string_view target,
                          const std::atomic<bool>* cancel);
    ViewerResponse diff(const Query& req);
    ViewerResponse trace(const Query& req);

    std::filesystem::path folder_;  // canonical
    FileScope scope_;               // the folder: every file a scene names lies in it
    std::string default_scene_;
    std::function<void(const RenderJob&)> check_;
    std::mutex mutex_;                                                   // guards `current_`
    std::map<std::string, std::shared_ptr<std::atomic<bool>>> current_;  // per client: its render
    FileCache files_;    // each mesh file and image read once (again when it changes)
    AccelCache accels_;  // a slider that moves no shape reuses the scene's BVH
    TriangleListCache triangle_lists_;    // and the rasterizer's triangles
    OccluderCubeCache occluder_cubes_;    // and its shadow rays' occluders
    RendererPool renderers_{kRenderers};  // a drag's frames draw into the last one's buffers
    std::atomic<int> renders_{0};         // in progress (/api/status)
};

}  // namespace svetlo
