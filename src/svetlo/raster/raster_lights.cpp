#include "svetlo/raster/raster_lights.h"

#include <algorithm>

#include "svetlo/core/sampling.h"
#include "svetlo/shading/lights.h"

namespace svetlo {

namespace {

/// The k-th of n points of the R2 low-discrepancy sequence (Roberts 2018) in [0,1)^2.
vec2 r2(int k) {
    constexpr double g = 1.32471795724474602596;  // the plastic number
    double x = 0.5 + k / g, y = 0.5 + k / (g * g);
    return vec2(static_cast<float>(x - std::floor(x)), static_cast<float>(y - std::floor(y)));
}

}  // namespace

std::vector<VirtualLight> area_light_vpls(const AreaLight& light) {
    std::vector<VirtualLight> out;
    vec3 n = glm::cross(light.edge_u, light.edge_v);
    float area = glm::length(n);
    if (!(area > 0.0f)) return out;
    n /= area;
    int side = static_cast<int>(std::sqrt(static_cast<double>(kVplsPerEmitter)));
    int count = side * side;
    for (int k = 0; k < count; ++k) {
        vec2 u = stratified_sample(k, count, vec2(0.5f));
        out.push_back({light.corner + u.x * light.edge_u + u.y * light.edge_v, n,
                       light.radiance * (area / static_cast<float>(count)),
                       area / static_cast<float>(count)});
    }
    return out;
}

std::vector<VirtualLight> triangle_vpls(const EmitterTriangles& tris) {
    std::vector<VirtualLight> out;
    size_t n = tris.radiance.size();
    std::vector<double> cdf(n);
    double total = 0.0;
    for (size_t t = 0; t < n; ++t) {
        total += 0.5 * glm::length(glm::cross(tris.p[3 * t + 1] - tris.p[3 * t],
                                              tris.p[3 * t + 2] - tris.p[3 * t]));
        cdf[t] = total;
    }
    if (!(total > 0.0)) return out;
    auto area_per = static_cast<float>(total / kVplsPerEmitter);
    for (int k = 0; k < kVplsPerEmitter; ++k) {
        // Stratified along the area CDF, then a low-discrepancy point inside the triangle.
        double x = (k + 0.5) / kVplsPerEmitter * total;
        size_t t = static_cast<size_t>(std::lower_bound(cdf.begin(), cdf.end(), x) - cdf.begin());
        t = std::min(t, n - 1);
        vec3 a = tris.p[3 * t], b = tris.p[3 * t + 1], c = tris.p[3 * t + 2];
        vec3 normal = glm::cross(b - a, c - a);
        if (!(glm::length(normal) > 0.0f)) continue;
        vec2 bary = sample_triangle(r2(k));
        out.push_back({bary.x * a + bary.y * b + (1.0f - bary.x - bary.y) * c,
                       glm::normalize(normal), tris.radiance[t] * area_per, area_per});
    }
    return out;
}

Color shade_point(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                  const RasterLights& lights, Color ambient, Color background) {
    const vec3 ng = frame.ng, ns = frame.ns;
    Color L(0.0f);
    if (bsdf.model == Bsdf::Model::Emissive && frame.front) L += bsdf.emission;
    L += bsdf.ambient * ambient;
    // Ideal mirrors and glass see the uniform environment (the background) only: a
    // rasterizer has no other surfaces to show in them. Glass without absorption passes all
    // of it, reflected or transmitted.
    if (bsdf.model == Bsdf::Model::Mirror) L += bsdf.reflect * background;
    if (bsdf.model == Bsdf::Model::Dielectric) L += background;
    if (!bsdf.has_lobes()) return L;
    for (const Light* light : lights.punctual) {
        PunctualSample s = sample_punctual(*light, p);
        float cos_theta = glm::dot(ns, s.wi);
        if (cos_theta <= 0.0f || glm::dot(ng, s.wi) <= 0.0f || is_black(s.irradiance)) continue;
        L += eval_bsdf(bsdf, ns, wo, s.wi) * s.irradiance * cos_theta;
    }
    for (const VirtualLight& v : lights.vpls) {
        vec3 d = v.p - p;
        float dist2 = glm::dot(d, d);
        if (!(dist2 > 0.0f)) continue;
        vec3 wi = d / std::sqrt(dist2);
        float cos_theta = glm::dot(ns, wi), cos_light = -glm::dot(v.n, wi);
        if (cos_theta <= 0.0f || cos_light <= 0.0f || glm::dot(ng, wi) <= 0.0f) continue;
        Color irradiance = v.power * (cos_light / std::max(dist2, v.min_dist2));
        L += eval_bsdf(bsdf, ns, wo, wi) * irradiance * cos_theta;
    }
    return L;
}

}  // namespace svetlo
