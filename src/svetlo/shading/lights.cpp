#include "svetlo/shading/lights.h"

namespace svetlo {

float spot_cone_factor(const SpotLight& light, vec3 light_to_point) {
    float cos_theta = glm::dot(light.direction, light_to_point);
    float cos_inner = std::cos(radians(light.inner_deg));
    float cos_outer = std::cos(radians(light.outer_deg));
    if (cos_theta >= cos_inner) return 1.0f;
    if (cos_theta <= cos_outer) return 0.0f;
    float t = (cos_theta - cos_outer) / (cos_inner - cos_outer);
    return t * t * (3.0f - 2.0f * t);
}

PunctualSample sample_punctual(const Light& light, vec3 p) {
    PunctualSample s;
    if (const auto* point = std::get_if<PointLight>(&light)) {
        vec3 d = point->position - p;
        float d2 = glm::dot(d, d);
        s.distance = std::sqrt(d2);
        s.wi = d / s.distance;
        s.irradiance = point->intensity / d2;  // E = I / d^2 (inverse-square law)
    } else if (const auto* sun = std::get_if<DirectionalLight>(&light)) {
        s.wi = -sun->direction;
        s.irradiance = sun->irradiance;
    } else if (const auto* spot = std::get_if<SpotLight>(&light)) {
        vec3 d = spot->position - p;
        float d2 = glm::dot(d, d);
        s.distance = std::sqrt(d2);
        s.wi = d / s.distance;
        s.irradiance = spot->intensity * (spot_cone_factor(*spot, -s.wi) / d2);
    }
    return s;
}

}  // namespace svetlo
