// The Whitted ray tracer (Whitted, "An Improved Illumination Model for Shaded Display",
// CACM 1980): at the closest hit, the emitted radiance, the empirical ambient term, direct
// light from every light through shadow rays (area lights and emissive objects sampled by
// area, which gives soft shadows), and recursion into the ideal mirror and refracted
// directions up to render.max_depth. Pixels are jittered-supersampled with render.spp.
#pragma once

#include "svetlo/scene/renderer.h"

namespace svetlo {

class WhittedRenderer final : public Renderer {
public:
    Capabilities capabilities() const override {
        return {.name = "whitted", .traces_samples = true, .debug_aovs = {"bvh_cost"}};
    }
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
};

}  // namespace svetlo
