// The interface every engine implements, and what a render returns. Engines are an open set:
// apps/svetlo/engines.cpp maps names to factories.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// The auxiliary buffers (contract: --aov NAME=FILE).
inline const std::vector<std::string>& aov_names() {
    static const std::vector<std::string> names = {"depth", "normal", "albedo", "visibility"};
    return names;
}

/// The teaching buffers: the rasterizer's (docs/shadows.md) light 0's shadow map (a cube map
/// unfolded) and the shadow-volume stencil count per pixel; radiosity's patch mesh with each
/// element's value (docs/radiosity.md).
inline const std::vector<std::string>& debug_aov_names() {
    static const std::vector<std::string> names = {"shadow_map", "stencil", "patches"};
    return names;
}

struct RenderOptions {
    int threads = 0;                      // 0 = all cores
    double time_budget = 0.0;             // seconds, 0 = none (--time; progressive engines)
    bool spp_caps_time = false;           // with a budget, stop at render.spp too (--spp given)
    bool progress = false;                // draw a progress bar on stderr
    std::vector<std::string> aovs;        // which of aov_names() to fill
    std::vector<std::string> debug_aovs;  // which of debug_aov_names() to make
};

struct RenderStats {
    double seconds = 0.0;        // rendering, excluding scene setup
    double setup_seconds = 0.0;  // acceleration structure build and the like
    uint64_t rays = 0;           // all rays traced (camera, shadow, secondary)
    uint64_t triangles = 0;      // triangles set up for rasterization
    uint64_t nonfinite = 0;      // samples whose radiance was NaN or infinite: dropped (black)
    int passes = 0;              // progressive engines: passes (samples per pixel) done
    std::string detail;          // what else the engine reports in the summary line
};

struct RenderResult {
    Image color;  // linear radiance
    std::map<std::string, Image> aovs;
    RenderStats stats;
};

/// What the first hit of one camera sample gives the AOVs (the engines average it per pixel).
struct AovSample {
    float depth = 0.0f;       // distance from the camera
    vec3 normal{0.0f};        // world-space shading normal, toward the viewer
    Color albedo{0.0f};       // albedo_of the material
    float visibility = 1.0f;  // the fraction of light 0 that reaches the point
};

/// The images a render fills: the colour, and the AOVs asked for (depth, normal and albedo
/// zero, visibility one), with pointers indexed like aov_names() (null when not asked for).
struct AovTargets {
    bool want[4] = {false, false, false, false};
    Image* image[4] = {nullptr, nullptr, nullptr, nullptr};
    bool any = false;
};
inline AovTargets prepare_result(RenderResult& result, const std::vector<std::string>& aovs,
                                 int width, int height) {
    result.color = Image(width, height);
    AovTargets t;
    for (const std::string& name : aovs) {
        for (size_t k = 0; k < aov_names().size(); ++k) {
            if (name != aov_names()[k]) continue;
            t.want[k] = true;
            result.aovs[name] = Image(width, height, k == 3 ? Color(1.0f) : Color(0.0f));
        }
    }
    for (size_t k = 0; k < 4; ++k) t.image[k] = t.want[k] ? &result.aovs[aov_names()[k]] : nullptr;
    t.any = !result.aovs.empty();
    return t;
}

class Renderer {
public:
    virtual ~Renderer() = default;
    virtual RenderResult render(const Scene& scene, const RenderOptions& options) = 0;
};

}  // namespace svetlo
