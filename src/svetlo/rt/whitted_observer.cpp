#include "svetlo/rt/whitted_observer.h"

#include <cmath>

#include "svetlo/rt/light_trace_ray.h"

namespace svetlo {

int WhittedTraceLog::ray(const Ray& ray, int depth, const char* kind, int parent, Color to_pixel,
                         float t) {
    TraceRay r;
    r.kind = kind;
    r.parent = parent;
    r.depth = depth;
    r.origin = ray.o;
    r.direction = glm::normalize(ray.d);
    r.t = std::isfinite(t) ? t * glm::length(ray.d) : kInfinity;
    r.set("weight", to_pixel);
    if (fresnel_ >= 0.0f) r.set("fresnel", {fresnel_});
    fresnel_ = -1.0f;
    return trace_.add(std::move(r));
}

void WhittedTraceLog::adds(int self, Color contribution) {
    trace_.rays[self].contribution = contribution;
}

void WhittedTraceLog::hit(int self, const SurfaceHit& hit, vec3 ns, bool front) {
    describe_hit(trace_.rays[self], material_names_, hit.material, hit.p, ns, front);
}

void WhittedTraceLog::shadow_ray(int parent, int depth, vec3 p, vec3 ng, vec3 wi, float distance,
                                 int light, float v, Color f_e_cos, float count, Color to_pixel) {
    TraceRay r = light_trace_ray("shadow", parent, depth, p, ng, wi, distance, v);
    r.contribution = to_pixel * f_e_cos * (v / count);
    r.set("light", {static_cast<float>(light)});
    r.set("visibility", {v});
    r.set("unoccluded", f_e_cos / count);
    trace_.add(std::move(r));
}

}  // namespace svetlo
