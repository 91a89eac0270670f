#include "svetlo/raster/raster_lights.h"

#include <algorithm>
#include <cmath>

#include "svetlo/core/sampling.h"
#include "svetlo/shading/direct_light.h"

namespace svetlo {

namespace {

/// Each source sampled at its fixed VPLs.
struct VplSampling {
    const RasterLights& lights;
    int count(size_t i, const LightSet::Source& s) const {
        return s.delta ? 1 : static_cast<int>(lights.vpls[i].size());
    }
    LightSample sample(size_t i, const LightSet::Source& s, int k, vec3 p) const {
        if (s.delta) return lights.set.sample(s, p, vec2(0.0f), 0.0f);
        return lights.set.sample_at(lights.vpls[i][static_cast<size_t>(k)], p, lights.min_dist2[i]);
    }
};

}  // namespace

RasterLights::RasterLights(const Scene& scene, int threads, IblCache* ibl)
    : set(scene), environment(scene, threads, ibl) {
    const int n = scene.render.area_light_points;
    const int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
    for (const LightSet::Source& s : set.sources()) {
        std::vector<AreaPoint> points;
        if (!s.delta) {
            // Over the primitive's parameters, the centres of a side x side grid when n is a
            // square (8 x 8 by default), else a rank-1 lattice (the k-th column, and the R2
            // sequence's second coordinate); a primitive picked by area from the R2 sequence's
            // first (so that the grid's rows do not all land on one primitive).
            for (int k = 0; k < n; ++k) {
                const vec2 u = side * side == n
                                   ? stratified_sample(k, n, vec2(0.5f))
                                   : vec2((static_cast<float>(k) + 0.5f) / static_cast<float>(n),
                                          r2_sequence(k).y);
                points.push_back(set.sample_area(s, u, r2_sequence(k).x));
            }
            any_vpl = true;
        }
        vpls.push_back(std::move(points));
        min_dist2.push_back(s.area / static_cast<float>(n));
    }
}

namespace {

/// The perceptual roughness of the prefiltered levels that blur the map as a rough
/// transmission of GGX alpha spreads what lies behind it (eta = n_t / n_i): a microfacet
/// tilted by theta turns a refracted ray by about |1 - 1/eta| theta where it turns a reflected
/// one by 2 theta (small angles), so the reflection's levels at alpha |1 - 1/eta| / 2.
float transmitted_roughness(const Bsdf& b, bool front) {
    const float eta = front ? b.ior : 1.0f / b.ior;
    return std::sqrt(b.alpha * std::abs(1.0f - 1.0f / eta) * 0.5f);
}

}  // namespace

Color unlit_point(const Bsdf& bsdf, const ShadingFrame& frame, vec3 wo, Color ambient,
                  Color background, const ImageBasedLighting& environment) {
    Color L = emitted_and_ambient(bsdf, frame, ambient);
    if (environment.active()) {  // image-based lighting (image_based_lighting.h)
        // A clear coat (bsdf.cpp's layering): its own lobe of F0 0.04 about its own normal,
        // by the split sum too, and the base's light seen through it, times 1 - coat F_c at
        // the viewer's angle.
        float through = 1.0f;
        if (bsdf.model == Bsdf::Model::CookTorrance && bsdf.coat > 0.0f) {
            const vec3 nc = has_coat_normal(bsdf) ? bsdf.coat_normal : frame.ns;
            const float cos_oc = std::clamp(glm::dot(nc, wo), 0.0f, 1.0f);
            through = under_coat(bsdf, cos_oc);
            L += bsdf.occlusion * bsdf.coat *
                 environment.glossy(reflect(wo, nc), cos_oc, std::sqrt(bsdf.coat_alpha),
                                    Color(0.04f));
        }
        if (bsdf.has_lobes())
            L +=
                through * bsdf.diffuse * kInvPi * bsdf.occlusion * environment.irradiance(frame.ns);
        if (bsdf.model == Bsdf::Model::CookTorrance)  // the glossy part: split sum
            L += through * bsdf.occlusion *
                 environment.glossy(reflect(wo, frame.ns), glm::dot(frame.ns, wo),
                                    std::sqrt(bsdf.alpha), bsdf.specular, bsdf.f90);
        if (bsdf.model == Bsdf::Model::Mirror)
            L += bsdf.reflect * environment.environment().radiance(reflect(wo, frame.ns));
        if (bsdf.model == Bsdf::Model::Dielectric) L += environment.environment().radiance(-wo);
        // A Cook-Torrance surface's transmission: what lies behind is the map, unrefracted;
        // through a rough one, blurred by the prefiltered levels (docs/raster.md).
        if (bsdf.model == Bsdf::Model::CookTorrance && !is_black(bsdf.transmit)) {
            const Color behind =
                rough_transmission(bsdf)
                    ? environment.blurred(-wo, transmitted_roughness(bsdf, frame.front))
                    : environment.environment().radiance(-wo);
            L += transmitted_weight(bsdf, glm::dot(frame.ns, wo)) * behind;
        }
        return L;
    }
    // Ideal mirrors and glass see the uniform environment (the background) only: a
    // rasterizer has no other surfaces to show in them. Glass without absorption passes all
    // of it, reflected or transmitted.
    if (bsdf.model == Bsdf::Model::Mirror) L += bsdf.reflect * background;
    if (bsdf.model == Bsdf::Model::Dielectric) L += background;
    if (bsdf.model == Bsdf::Model::CookTorrance && !is_black(bsdf.transmit))
        L += transmitted_weight(bsdf, glm::dot(frame.ns, wo)) * background;
    return L;
}

Color shade_point(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                  const RasterLights& lights, Color ambient, Color background,
                  const LightVisibility& vis, size_t sample) {
    return unlit_point(bsdf, frame, wo, ambient, background, lights.environment) +
           direct_light(lights.set, bsdf, p, frame, wo, VplSampling{lights},
                        [&](size_t source, const LightSample&) { return vis.at(source, sample); });
}

Color shade_point_per_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                            const RasterLights& lights, Color ambient, Color background,
                            Color* per_light) {
    const auto& sources = lights.set.sources();
    VplSampling sampling{lights};
    auto unmasked = [](size_t, const LightSample&) { return 1.0f; };
    for (size_t index = 0; index < sources.size(); ++index) {
        per_light[index] = bsdf.has_lobes() ? source_light(sources[index], index, bsdf, p, frame,
                                                           wo, sampling, unmasked)
                                            : Color(0.0f);
    }
    return unlit_point(bsdf, frame, wo, ambient, background, lights.environment);
}

}  // namespace svetlo
