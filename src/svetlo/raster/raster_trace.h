// svetlo trace for the rasterizer (docs/trace.md): a fragment is not a ray, so the pixel is
// explained by drawing it again with the pipeline itself. The frame is drawn whole once
// (its pixel is the total), once with no light (emission and the ambient term), and, per
// light, alone with and without its shadow technique: the light's term, its visibility
// under the technique, and what it adds. The fragment's attributes come from the depth,
// normal and albedo AOVs of the same pixel.
#pragma once

#include "svetlo/scene/renderer.h"

namespace svetlo {

/// Fills *options.trace for pixel (trace->x, trace->y), drawing with `engine` (the
/// rasterizer); returns the render of that pixel alone, with its depth, normal and albedo.
RenderResult trace_raster_pixel(Renderer& engine, const Scene& scene, const RenderOptions& options);

}  // namespace svetlo
