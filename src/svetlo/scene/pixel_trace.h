// One camera sample of one pixel, followed through an engine (docs/trace.md: `svetlo trace`;
// docs/trace.md): every ray it casts or path vertex it makes, with what each adds to the
// pixel. An engine records into it when RenderOptions::trace points at one; `total` is then
// the sample's radiance, the number the pixel gets from it.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "svetlo/core/math.h"

namespace svetlo {

/// A named number or vector of a ray: a Fresnel weight, a pdf, an MIS weight, a throughput.
struct TraceValue {
    std::string name;
    std::vector<float> value;
};

struct TraceRay {
    /// camera, reflect, refract, shadow (Whitted's), bsdf (a path's next ray), light (a path's
    /// light sample, or a light's term at a raster fragment).
    std::string kind;
    int parent = -1;  // the index of the ray it branches from; -1 for the camera's
    int depth = 0;    // bounces from the camera
    vec3 origin{0.0f};
    vec3 direction{0.0f};  // unit, world space
    float t = kInfinity;   // distance to what the ray meets, scene units; infinity: nothing
    /// What this ray adds to the pixel, linear RGB, W/(m^2 sr): the radiance it brings back
    /// times every weight on its way to the camera. The contributions sum to the total.
    Color contribution{0.0f};
    std::string note;  // what it met, in words
    std::vector<TraceValue> values;

    TraceRay& set(std::string name, std::initializer_list<float> value) {
        values.push_back({std::move(name), std::vector<float>(value)});
        return *this;
    }
    TraceRay& set(std::string name, vec3 v) { return set(std::move(name), {v.x, v.y, v.z}); }
};

/// Notes on `ray` what it met: material `material` of the scene (or a light's own, past the
/// scene's), at point p with shading normal ns, from the front or the back.
inline void describe_hit(TraceRay& ray, const std::vector<std::string>& material_names,
                         uint32_t material, vec3 p, vec3 ns, bool front) {
    ray.note = (material < material_names.size() ? "material " + material_names[material]
                                                 : std::string("a light"));
    ray.note += front ? ", front" : ", back";
    ray.set("point", p).set("normal", ns);
}

struct PixelTrace {
    int x = 0, y = 0;  // the pixel, in the full film
    int sample = 0;    // the camera sample followed (a path's pass)
    Color total{0.0f};
    bool recorded = false;  // the engine reached the sample
    std::vector<TraceRay> rays;
    std::vector<std::string> notes;  // what holds for the whole sample (the shadow technique)

    /// Adds a ray; returns its index, the parent of the rays it spawns.
    int add(TraceRay ray) {
        rays.push_back(std::move(ray));
        return static_cast<int>(rays.size()) - 1;
    }
    bool at(int i, int j) const { return i == x && j == y; }
};

/// Ends a trace with the sample's radiance c: what the pixel gets from it, black when c (or an
/// AOV) is not finite, as every engine drops such a sample.
inline void record_total(PixelTrace& trace, Color c, bool finite) {
    trace.total = finite ? c : Color(0.0f);
    if (!finite) trace.notes.push_back("the sample is not finite: the engine drops it (black)");
    trace.recorded = true;
}

}  // namespace svetlo
