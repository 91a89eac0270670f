// The contract's camera, written again here as an independent reference for the rasterizer's
// tests (docs/scene-format.md, "camera"): the ray through film point (x, y), x to the right
// and y downward from the top-left corner, in [0, 1]^2. The direction is unit length.
#pragma once

#include "svetlo/geometry/ray.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

inline Ray contract_camera_ray(const Camera& c, int width, int height, float x, float y) {
    vec3 forward = glm::normalize(c.look_at - c.position);
    vec3 right = glm::normalize(glm::cross(forward, c.up));
    vec3 up = glm::cross(right, forward);
    float aspect = static_cast<float>(width) / static_cast<float>(height);
    float sx = 2.0f * x - 1.0f, sy = 1.0f - 2.0f * y;  // [-1, 1], y up
    if (c.type == Camera::Type::Orthographic) {
        float half_h = 0.5f * c.height, half_w = half_h * aspect;
        return Ray{c.position + sx * half_w * right + sy * half_h * up, forward, kInfinity};
    }
    float half_h = std::tan(0.5f * radians(c.fov_deg)), half_w = half_h * aspect;
    return Ray{c.position, glm::normalize(forward + sx * half_w * right + sy * half_h * up),
               kInfinity};
}

}  // namespace svetlo
