// The engines: the factory table (name -> Renderer), and what each can do (its
// Capabilities), from which the command line's checks and their messages are made.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "svetlo/scene/renderer.h"

namespace svetlo {

/// The renderer called `name`; throws Error naming render.engine for one not built yet.
std::unique_ptr<Renderer> make_renderer(const std::string& name, const std::string& file);

/// Every engine's capabilities, in the order of the factory table.
const std::vector<Capabilities>& engine_capabilities();

/// The capabilities of engine `name`; throws Error naming render.engine for an unknown one.
const Capabilities& capabilities_of(const std::string& name, const std::string& file);

/// The engines that have `what`, as a reader says it: "path", "raster or radiosity".
std::string engines_with(const std::function<bool(const Capabilities&)>& what);

/// The technique a render's settings choose, named as the lecture names it: "Gouraud shading,
/// shadow volume, z-fail", "shadow map, PCSS" (Phong shading is the rasterizer's own),
/// "Whitted ray tracing", "path tracing, guided", "radiosity, Gauss-Seidel". The compare
/// sheets title their columns with it (docs/compare.md).
std::string technique_name(const RenderSettings& render);

/// Why `scene` cannot make debug AOV `name` ("needs render.engine raster with render.shadows
/// map"); empty when it can, or when `name` is not a debug AOV.
std::string debug_aov_refusal(const Scene& scene, const std::string& name);

}  // namespace svetlo
