#include "svetlo/job/renderer_pool.h"

#include "svetlo/job/engines.h"

namespace svetlo {

RendererPool::Lease RendererPool::take(const std::string& engine,
                                       const std::filesystem::path& scene_file) {
    {
        std::lock_guard lock(mutex_);
        std::vector<std::unique_ptr<Renderer>>& idle = idle_[engine];
        if (!idle.empty()) {
            std::unique_ptr<Renderer> renderer = std::move(idle.back());
            idle.pop_back();
            return Lease(*this, engine, std::move(renderer));
        }
    }
    return Lease(*this, engine, make_renderer(engine, scene_file.string()));
}

void RendererPool::give_back(const std::string& engine, std::unique_ptr<Renderer> renderer) {
    std::lock_guard lock(mutex_);
    std::vector<std::unique_ptr<Renderer>>& idle = idle_[engine];
    if (idle.size() < keep_) idle.push_back(std::move(renderer));
}

}  // namespace svetlo
