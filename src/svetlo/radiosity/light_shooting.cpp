#include "svetlo/radiosity/light_shooting.h"

#include "svetlo/core/sampling.h"
#include "svetlo/geometry/ray.h"

namespace svetlo {

namespace {

/// Whether the light sample is visible from x (n its side's normal).
bool sample_visible(const Accel& accel, vec3 x, vec3 n, const LightSample& s) {
    vec3 o = offset_ray_origin(x, n, s.wi);
    if (!std::isfinite(s.distance)) return !accel.occluded(Ray{o, s.wi, kInfinity});
    vec3 target = s.delta ? s.p : offset_ray_origin(s.p, s.n, -s.wi);
    return !accel.occluded(Ray{o, target - o, 1.0f});
}

/// The sample's irradiance on the side n, before visibility (zero behind it).
Color facing_irradiance(const LightSample& s, vec3 n) {
    float cos_theta = glm::dot(n, s.wi);
    if (!(cos_theta > 0.0f) || is_black(s.irradiance)) return Color(0.0f);
    return s.irradiance * cos_theta;
}

}  // namespace

Color light_irradiance(const LightSet& lights, const Accel& accel, vec3 x, vec3 n,
                       LightSources which, int samples, Rng& rng, uint64_t& rays) {
    Color E(0.0f);
    for (const LightSet::Source& source : lights.sources()) {
        if (source.delta) {
            LightSample s = lights.sample(source, x, vec2(0.0f), 0.0f);
            Color e = facing_irradiance(s, n);
            if (is_black(e)) continue;
            ++rays;
            if (sample_visible(accel, x, n, s)) E += e;
            continue;
        }
        if (which == LightSources::Delta) continue;
        Color sum(0.0f);
        for (int k = 0; k < samples; ++k) {
            vec2 u = stratified_sample(k, samples, rng.next_2d());
            LightSample s = lights.sample(source, x, u, rng.next_float());
            Color e = facing_irradiance(s, n);
            if (is_black(e)) continue;
            ++rays;
            if (sample_visible(accel, x, n, s)) sum += e;
        }
        E += sum / static_cast<float>(samples);
    }
    return E;
}

Color sky_irradiance(const Accel& accel, const Environment& environment, vec3 x, vec3 n, int rays,
                     Rng& rng) {
    if (environment.is_black()) return Color(0.0f);
    if (environment.is_map()) {
        // E = integral of L cos over the hemisphere: 4 x `rays` directions by the map's
        // importance, L cos / pdf for those that reach it.
        const int count = 4 * rays;
        Color sum(0.0f);
        for (int r = 0; r < count; ++r) {
            const EnvironmentSample s =
                environment.sample(stratified_sample(r, count, rng.next_2d()));
            const float cos_theta = glm::dot(n, s.wi);
            if (cos_theta <= 0.0f || !(s.pdf > 0.0f)) continue;
            if (!accel.occluded(Ray{offset_ray_origin(x, n, s.wi), s.wi, kInfinity}))
                sum += s.radiance * (cos_theta / s.pdf);
        }
        return sum / static_cast<float>(count);
    }
    const Color background = environment.uniform();
    const Frame frame = Frame::from_normal(n);
    int open = 0;
    for (int r = 0; r < rays; ++r) {
        vec3 w =
            frame.to_world(sample_cosine_hemisphere(stratified_sample(r, rays, rng.next_2d())));
        if (!accel.occluded(Ray{offset_ray_origin(x, n, w), w, kInfinity})) ++open;
    }
    return kPi * background * (static_cast<float>(open) / static_cast<float>(rays));
}

float light0_visibility(const LightSet& lights, const Accel& accel, vec3 x, vec3 n, int samples,
                        Rng& rng, uint64_t& rays) {
    const LightSet::Source* source = lights.source_of_light(0);
    if (!source) return 1.0f;
    const int count = source->delta ? 1 : std::max(samples, 16);
    int lit = 0, facing = 0;
    for (int k = 0; k < count; ++k) {
        vec2 u = source->delta ? vec2(0.0f) : stratified_sample(k, count, rng.next_2d());
        LightSample s = lights.sample(*source, x, u, source->delta ? 0.0f : rng.next_float());
        if (is_black(facing_irradiance(s, n))) continue;
        ++facing;
        ++rays;
        if (sample_visible(accel, x, n, s)) ++lit;
    }
    return facing == 0 ? 1.0f : static_cast<float>(lit) / static_cast<float>(facing);
}

}  // namespace svetlo
