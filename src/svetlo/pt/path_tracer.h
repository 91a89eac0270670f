// The path tracer, "engine": "path": svetlo's physically based reference (docs/path.md). It
// renders in passes of one sample per pixel, each pass a new photon map when there are
// caustics to find (caustic_photons.h), until render.spp passes are done or --time's budget is
// spent; the image is the mean of the passes done. Each pixel's sample of each pass draws
// from its own random stream, so the image does not depend on the thread count.
#pragma once

#include "svetlo/scene/renderer.h"

namespace svetlo {

class PathRenderer final : public Renderer {
public:
    Capabilities capabilities() const override {
        return {.name = "path",
                .progressive = true,
                .shows_passes = true,
                .checkpoints = true,
                .traces_samples = true,
                .debug_aovs = {"bvh_cost", "path_depth"},
                .film_bytes_per_pixel = 40};
    }
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
};

}  // namespace svetlo
