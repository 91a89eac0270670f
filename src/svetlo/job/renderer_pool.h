// Renderers kept from one request to the next (svetlo serve), as a viewport keeps its GL
// context: the rasterizer keeps its large buffers (vertices, set-up triangles, the shadow
// techniques' passes) from one frame to the next, and a drag's frames then draw into memory
// already mapped instead of faulting in fresh pages each time (docs/viewer.md, "Where the
// time goes"). A renderer draws one frame at a time: a request takes one for its render, a
// new one when none is idle, and gives it back when done.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "svetlo/scene/renderer.h"

namespace svetlo {

class RendererPool {
public:
    /// Keeps at most `idle_per_engine` idle renderers of each engine (the server's threads:
    /// no more can be busy at once).
    explicit RendererPool(size_t idle_per_engine) : keep_(idle_per_engine) {}

    /// A renderer taken for one render; given back to the pool when it ends.
    class Lease {
    public:
        Lease(RendererPool& pool, std::string engine, std::unique_ptr<Renderer> renderer)
            : pool_(pool), engine_(std::move(engine)), renderer_(std::move(renderer)) {}
        ~Lease() { pool_.give_back(engine_, std::move(renderer_)); }
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        Renderer* operator->() const { return renderer_.get(); }

    private:
        RendererPool& pool_;
        std::string engine_;
        std::unique_ptr<Renderer> renderer_;
    };

    /// An idle renderer of `engine`, or a new one (make_renderer: an unknown engine throws
    /// Error naming `scene_file`).
    Lease take(const std::string& engine, const std::filesystem::path& scene_file);

private:
    void give_back(const std::string& engine, std::unique_ptr<Renderer> renderer);

    size_t keep_;
    std::mutex mutex_;  // guards idle_
    std::map<std::string, std::vector<std::unique_ptr<Renderer>>> idle_;
};

}  // namespace svetlo
