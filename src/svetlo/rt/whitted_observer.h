// What `svetlo trace` records of a Whitted sample (docs/trace.md): its tree of rays, reported
// by the tracer one call per event. The tracer holds a pointer that is null when nobody
// traces; WhittedTraceLog is the observer that writes a PixelTrace.
#pragma once

#include <string>
#include <vector>

#include "svetlo/geometry/geometry.h"
#include "svetlo/scene/pixel_trace.h"

namespace svetlo {

class WhittedObserver {
public:
    virtual ~WhittedObserver() = default;
    /// A ray of the tree: its `kind` ("camera", "reflect", "refract"), the ray it branches
    /// from (-1: none), its weight to the pixel; it meets something at t (in units of |d|,
    /// or infinity). Returns its id, the `parent` of the rays that branch from it.
    virtual int ray(const Ray& ray, int depth, const char* kind, int parent, Color to_pixel,
                    float t) = 0;
    /// The next ray branches with this Fresnel weight (a dielectric's reflection or
    /// refraction).
    virtual void fresnel(float weight) = 0;
    /// Ray `self` left the scene, or met a surface that emits or is lit by the ambient term:
    /// what it adds to the pixel.
    virtual void adds(int self, Color contribution) = 0;
    /// Ray `self` met a surface.
    virtual void hit(int self, const SurfaceHit& hit, vec3 ns, bool front) = 0;
    /// The shadow ray from p toward a sample of light `light` (its index in the scene's
    /// lights; -1 for an emitter): visibility v, and the sample's f E cos, `count` samples of
    /// the light taken.
    virtual void shadow_ray(int parent, int depth, vec3 p, vec3 ng, vec3 wi, float distance,
                            int light, float v, Color f_e_cos, float count, Color to_pixel) = 0;
};

/// The observer of svetlo trace: an entry of `trace` per ray, parents linked.
class WhittedTraceLog final : public WhittedObserver {
public:
    WhittedTraceLog(PixelTrace& trace, const std::vector<std::string>& material_names)
        : trace_(trace), material_names_(material_names) {}

    int ray(const Ray& ray, int depth, const char* kind, int parent, Color to_pixel,
            float t) override;
    void fresnel(float weight) override { fresnel_ = weight; }
    void adds(int self, Color contribution) override;
    void hit(int self, const SurfaceHit& hit, vec3 ns, bool front) override;
    void shadow_ray(int parent, int depth, vec3 p, vec3 ng, vec3 wi, float distance, int light,
                    float v, Color f_e_cos, float count, Color to_pixel) override;

private:
    PixelTrace& trace_;
    const std::vector<std::string>& material_names_;
    float fresnel_ = -1.0f;  // the Fresnel weight of the next ray (-1: none)
};

}  // namespace svetlo
