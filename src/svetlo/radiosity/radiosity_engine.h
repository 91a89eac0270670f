// The radiosity engine, "engine": "radiosity" (docs/radiosity.md): the scene's surfaces as a
// patch mesh (patch_mesh.h), point, spot and directional lights and the background shot onto
// it, the equation solved by the chosen solver (solver.h), independently of the view, and
// then drawn from the camera through the rasterizer's item buffer (display.h). Only the
// diffuse part of each material takes part: a mirror or glass shows black. The render is three
// steps, each a function of radiosity_engine.cpp: make_elements, solve, display_window.
#pragma once

#include "svetlo/scene/renderer.h"

namespace svetlo {

class RadiosityRenderer final : public Renderer {
public:
    Capabilities capabilities() const override {
        return {.name = "radiosity",
                .shows_passes = true,  // the progressive solver's snapshots
                .checkpoints = true,   // the progressive solve's
                .whole_frame = true,
                .patch_mesh = true,
                .debug_aovs = {"patches"},
                .film_bytes_per_pixel = 48};
    }
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
};

}  // namespace svetlo
