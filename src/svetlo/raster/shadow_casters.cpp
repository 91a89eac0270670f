#include "svetlo/raster/shadow_casters.h"

#include "svetlo/core/sampling.h"

namespace svetlo {

namespace {

/// The caster of a delta light.
ShadowCaster delta_caster(const Light& light, uint32_t source) {
    ShadowCaster c;
    c.source = source;
    if (const auto* p = std::get_if<PointLight>(&light)) {
        c.position = p->position;
    } else if (const auto* s = std::get_if<SpotLight>(&light)) {
        c.kind = ShadowCaster::Kind::Spot;
        c.position = s->position;
        c.direction = glm::normalize(s->direction);
        c.cos_outer = std::cos(radians(s->outer_deg));
    } else if (const auto* d = std::get_if<DirectionalLight>(&light)) {
        c.kind = ShadowCaster::Kind::Directional;
        c.direction = glm::normalize(d->direction);
    }
    return c;
}

/// A point caster on a light with area, moved `lift` metres off it along its emitting normal.
ShadowCaster area_caster(const AreaPoint& a, uint32_t source, float lift) {
    ShadowCaster c;
    c.source = source;
    c.normal = a.surface.n;
    c.position = a.surface.p + lift * a.surface.n;
    return c;
}

/// Every source's casters in order: a delta light's own, and for a light with area those
/// that area(index, source, casters) adds.
template <class Area>
std::vector<ShadowCaster> casters_of(const Scene& scene, const LightSet& lights, Area&& area) {
    std::vector<ShadowCaster> casters;
    const auto& sources = lights.sources();
    for (uint32_t i = 0; i < sources.size(); ++i) {
        const LightSet::Source& s = sources[i];
        if (s.delta) {
            casters.push_back(delta_caster(scene.lights[static_cast<size_t>(s.light_index)], i));
        } else {
            area(i, s, casters);
        }
    }
    return casters;
}

}  // namespace

std::vector<ShadowCaster> shadow_casters(const Scene& scene, const LightSet& lights,
                                         int points_per_area, float lift) {
    return casters_of(
        scene, lights,
        [&](uint32_t i, const LightSet::Source& s, std::vector<ShadowCaster>& casters) {
            if (!(s.area > 0.0f)) return;
            // Stratified over the primitives' parameters, the primitive picked by area from a
            // low-discrepancy sequence (as the rasterizer's VPLs).
            const int n = points_per_area > 0 ? points_per_area : 16;
            std::vector<AreaPoint> points;
            for (int k = 0; k < n; ++k)
                points.push_back(
                    lights.sample_area(s, stratified_sample(k, n, vec2(0.5f)), r2_sequence(k).x));
            if (points_per_area > 0) {
                for (const AreaPoint& a : points) casters.push_back(area_caster(a, i, lift));
                return;
            }
            // One caster at the centroid, facing the mean normal, as wide as the light.
            AreaPoint centre = points[0];
            vec3 p(0.0f), normal(0.0f);
            for (const AreaPoint& a : points) {
                p += a.surface.p;
                normal += a.surface.n;
            }
            centre.surface.p = p / static_cast<float>(n);
            centre.surface.n = glm::length(normal) > 0.0f ? glm::normalize(normal) : vec3(0.0f);
            ShadowCaster c = area_caster(centre, i, lift);
            c.size = std::sqrt(s.area);
            casters.push_back(c);
        });
}

std::vector<ShadowCaster> shadow_casters(const Scene& scene, const LightSet& lights,
                                         const std::vector<std::vector<AreaPoint>>& points) {
    return casters_of(scene, lights,
                      [&](uint32_t i, const LightSet::Source&, std::vector<ShadowCaster>& casters) {
                          for (const AreaPoint& a : points[i])
                              casters.push_back(area_caster(a, i, 0.0f));
                      });
}

}  // namespace svetlo
