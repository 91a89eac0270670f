// Rendering a JSON scene with one engine, as the known-answer tests do.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "svetlo/scene/renderer.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {

/// Renders scene `j` with a new `Engine` on `threads` threads, filling `aovs`.
template <class Engine>
RenderResult render_json(const nlohmann::json& j, int threads = 2,
                         std::vector<std::string> aovs = {}) {
    Scene scene = scene_from_json(j, "test.json");
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return Engine().render(scene, options);
}

}  // namespace svetlo
