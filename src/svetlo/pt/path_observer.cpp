#include "svetlo/pt/path_observer.h"

#include "svetlo/rt/light_trace_ray.h"

namespace svetlo {

void PathTraceLog::ray(const Ray& ray, int depth, float t, Color beta, float pdf, bool delta) {
    TraceRay r;
    r.kind = self_ < 0 ? "camera" : "bsdf";
    r.parent = self_;
    r.depth = depth;
    r.origin = ray.o;
    r.direction = ray.d;
    r.t = t;
    r.set("throughput", beta);
    if (self_ >= 0) r.set("pdf", {delta ? 0.0f : pdf});
    if (delta && self_ >= 0) r.note = "a delta lobe";
    self_ = trace_.add(std::move(r));
}

void PathTraceLog::background(Color contribution, float w) {
    trace_.rays[self_].contribution = contribution;
    trace_.rays[self_].set("mis_weight", {w}).note = "the background";
}

void PathTraceLog::vertex(const SurfaceHit& hit, const ShadingFrame& frame, int depth, Color beta) {
    describe_hit(trace_.rays[self_], material_names_, hit.material, hit.p, frame.ns, frame.front);
    parent_ = self_;
    depth_ = depth;
    beta_ = beta;
}

void PathTraceLog::emitted(Color contribution, float w) {
    trace_.rays[self_].contribution += contribution;
    trace_.rays[self_].set("mis_weight", {w});
}

void PathTraceLog::photons(Color radiance, Color contribution) {
    trace_.rays[self_].contribution += contribution;
    trace_.rays[self_].set("photon_radiance", radiance);
}

void PathTraceLog::roulette(float survive, bool ends) {
    trace_.rays[self_].set("survival", {survive});
    if (ends) trace_.rays[self_].note += "; Russian roulette ends the path here";
}

void PathTraceLog::light_sample(vec3 p, vec3 ng, vec3 wi, float distance, float pdf, float w,
                                float visible, Color c, float scale, const char* note) {
    TraceRay r = light_trace_ray("light", parent_, depth_, p, ng, wi, distance, visible);
    r.contribution = beta_ * c * scale;
    if (note) r.note = note;
    r.set("pdf", {pdf}).set("mis_weight", {w}).set("visibility", {visible});
    trace_.add(std::move(r));
}

}  // namespace svetlo
