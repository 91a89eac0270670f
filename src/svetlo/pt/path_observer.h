// What `svetlo trace` records of a path (docs/trace.md), reported by the integrator one call
// per event. The integrator holds a pointer that is null when nobody traces: each event is
// then one branch not taken, and the walk reads as the lecture's. PathTraceLog is the
// observer that writes a PixelTrace.
#pragma once

#include <string>
#include <vector>

#include "svetlo/geometry/geometry.h"
#include "svetlo/scene/pixel_trace.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

class PathObserver {
public:
    virtual ~PathObserver() = default;
    /// A camera ray (depth 0) or a BSDF-sampled one, carrying throughput `beta`, drawn with
    /// `pdf` (solid angle; `delta` for a delta lobe); it meets something at t (or nothing).
    virtual void ray(const Ray& ray, int depth, float t, Color beta, float pdf, bool delta) = 0;
    /// The ray left the scene: the background adds `contribution`, its MIS weight `w`.
    virtual void background(Color contribution, float w) = 0;
    /// The ray met a surface: the vertex whose light samples follow, with throughput `beta`.
    virtual void vertex(const SurfaceHit& hit, const ShadingFrame& frame, int depth,
                        Color beta) = 0;
    /// The surface met emits: `contribution`, its MIS weight `w`.
    virtual void emitted(Color contribution, float w) = 0;
    /// The photon map's caustic radiance at the vertex, and what it adds.
    virtual void photons(Color radiance, Color contribution) = 0;
    /// Russian roulette at the vertex: the chance to go on, and whether the path ends.
    virtual void roulette(float survive, bool ends) = 0;
    /// A light sample (or the background's) from vertex point p: its pdf (solid angle, with
    /// the light's choice), MIS weight, visibility, and what it adds to the vertex,
    /// unweighted by the vertex's throughput: `c` times `scale`.
    virtual void light_sample(vec3 p, vec3 ng, vec3 wi, float distance, float pdf, float w,
                              float visible, Color c, float scale, const char* note) = 0;
};

/// The observer of svetlo trace: every ray of the path and every light sample, an entry each
/// of `trace`, parents linked.
class PathTraceLog final : public PathObserver {
public:
    PathTraceLog(PixelTrace& trace, const std::vector<std::string>& material_names)
        : trace_(trace), material_names_(material_names) {}

    void ray(const Ray& ray, int depth, float t, Color beta, float pdf, bool delta) override;
    void background(Color contribution, float w) override;
    void vertex(const SurfaceHit& hit, const ShadingFrame& frame, int depth, Color beta) override;
    void emitted(Color contribution, float w) override;
    void photons(Color radiance, Color contribution) override;
    void roulette(float survive, bool ends) override;
    void light_sample(vec3 p, vec3 ng, vec3 wi, float distance, float pdf, float w, float visible,
                      Color c, float scale, const char* note) override;

private:
    PixelTrace& trace_;
    const std::vector<std::string>& material_names_;
    int self_ = -1;                // the entry of the ray being followed
    int parent_ = -1, depth_ = 0;  // the vertex whose light samples are being logged
    Color beta_{1.0f};             // and its throughput
};

}  // namespace svetlo
