// The engine factory table: name -> Renderer.
#pragma once

#include <memory>
#include <string>

#include "svetlo/scene/renderer.h"

namespace svetlo {

/// The renderer called `name`; throws Error naming render.engine for one not built yet.
std::unique_ptr<Renderer> make_renderer(const std::string& name, const std::string& file);

}  // namespace svetlo
