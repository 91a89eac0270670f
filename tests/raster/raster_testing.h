// What the rasterizer's tests share: a render of a JSON scene, an oblique camera over the
// floor, where a pixel's ray meets the floor, and normalised Phong in closed form.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "contract_camera.h"
#include "svetlo/core/image_io.h"
#include "svetlo/raster/camera_matrices.h"
#include "svetlo/raster/clipper.h"
#include "svetlo/raster/edge_function.h"
#include "svetlo/raster/lines.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/raster/raster_lights.h"
#include "svetlo/raster/simd_shading.h"
#include "svetlo/scene/scene_loader.h"
#include "svetlo/shading/mipmap.h"
#include "test_scenes.h"

namespace svetlo::raster_testing {

using json = nlohmann::json;

inline RenderResult render(const json& j, const std::string& engine = "raster",
                           std::vector<std::string> aovs = {}, int threads = 2) {
    Scene scene = scene_from_json(j, "test.json");
    scene.render.engine = engine;
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return RasterRenderer().render(scene, options);
}

/// A perspective camera looking obliquely down at the y = 0 plane.
inline json oblique(int w, int h) {
    return {{"camera", {{"position", {0.4, 2.2, 3.5}}, {"look_at", {0, 0, 0}}, {"fov", 50}}},
            {"film", {{"width", w}, {"height", h}}},
            {"render", {{"engine", "raster"}, {"spp", 1}, {"max_depth", 0}}}};
}

using test_scenes::floor_quad;

/// Where the ray through the centre of pixel (i, j) meets y = 0 (false if it does not).
inline bool floor_point(const Scene& scene, int i, int j, vec3& p) {
    Ray r = contract_camera_ray(scene.camera, scene.film.width, scene.film.height,
                                (i + 0.5f) / scene.film.width, (j + 0.5f) / scene.film.height);
    if (!(r.d.y < 0.0f)) return false;
    p = r.o - (r.o.y / r.d.y) * r.d;
    return true;
}

/// Normalised Phong under a point light, docs/shading.md's formula.
inline Color phong_closed_form(vec3 p, vec3 eye, vec3 light, Color intensity, float kd, float ks,
                               float n, float ka, float ambient) {
    vec3 nrm(0, 1, 0);
    vec3 d = light - p;
    float d2 = glm::dot(d, d);
    vec3 l = d / std::sqrt(d2), v = glm::normalize(eye - p);
    float cos_t = glm::dot(nrm, l);
    vec3 r = 2.0f * cos_t * nrm - l;
    float spec = (n + 2.0f) / (2.0f * kPi) * std::pow(std::max(0.0f, glm::dot(r, v)), n);
    return Color(ka * ambient) + (kd / kPi + ks * spec) * intensity * (cos_t / d2);
}

// The world point of a pixel comes from vertices snapped to 1/256 pixel: the interpolated
// point moves by at most 1/512 pixel times the world size of a pixel (here < 0.03 m / px at
// 96 px: 6e-5 m), which changes the lighting by well under 1e-3 relative.
inline constexpr float kSnapTolerance = 1e-3f;

}  // namespace svetlo::raster_testing
