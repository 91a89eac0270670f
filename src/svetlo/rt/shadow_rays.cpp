#include "svetlo/rt/shadow_rays.h"

namespace svetlo {

bool shadow_blocked(const RtScene& rt, vec3 p, vec3 ng, const LightSample& s, uint64_t& rays) {
    ++rays;
    if (std::isinf(s.distance))
        return rt.occluded(Ray{offset_ray_origin(p, ng, s.wi), s.wi, kInfinity});
    vec3 target = s.delta ? s.p : offset_ray_origin(s.p, s.n, -s.wi);
    Ray shadow{offset_ray_origin(p, ng, s.wi), vec3(0.0f), 1.0f};
    shadow.d = target - shadow.o;  // tmax = 1: the segment ends at the target
    return rt.occluded(shadow);
}

float light0_visibility(const RtScene& rt, vec3 p, vec3 ng, int samples, Rng& rng, uint64_t& rays) {
    const LightSet& lights = rt.lights();
    const LightSet::Source* light0 = lights.source_of_light(0);
    if (!light0) return 1.0f;  // no light, or an area light of no area
    if (light0->delta) {
        LightSample s = lights.sample(*light0, p, vec2(0.0f), 0.0f);
        if (glm::dot(ng, s.wi) <= 0.0f) return 1.0f;  // faces away from the light
        return shadow_blocked(rt, p, ng, s, rays) ? 0.0f : 1.0f;
    }
    int n = std::max(samples, 16);
    int facing = 0, visible = 0;
    for (int k = 0; k < n; ++k) {
        vec2 u = stratified_sample(k, n, rng.next_2d());
        LightSample s = lights.sample_at(lights.sample_area(*light0, u, 0.5f), p);
        if (glm::dot(ng, s.wi) <= 0.0f || glm::dot(s.n, s.wi) >= 0.0f) continue;
        ++facing;
        if (!shadow_blocked(rt, p, ng, s, rays)) ++visible;
    }
    return facing == 0 ? 1.0f : static_cast<float>(visible) / static_cast<float>(facing);
}

}  // namespace svetlo
