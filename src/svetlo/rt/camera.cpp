#include "svetlo/rt/camera.h"

namespace svetlo {

CameraRays::CameraRays(const Camera& camera, int width, int height) : camera_(camera) {
    forward_ = glm::normalize(camera.look_at - camera.position);
    right_ = glm::normalize(glm::cross(forward_, camera.up));
    up_ = glm::cross(right_, forward_);
    float aspect = static_cast<float>(width) / static_cast<float>(height);
    half_h_ = camera.type == Camera::Type::Perspective ? std::tan(radians(camera.fov_deg) * 0.5f)
                                                       : camera.height * 0.5f;
    half_w_ = half_h_ * aspect;
    focus_ = camera.focus_distance > 0.0f ? camera.focus_distance
                                          : glm::length(camera.look_at - camera.position);
}

Ray CameraRays::generate(float x, float y) const {
    float sx = (2.0f * x - 1.0f) * half_w_;  // right
    float sy = (1.0f - 2.0f * y) * half_h_;  // up
    if (camera_.type == Camera::Type::Perspective) {
        return Ray{camera_.position, glm::normalize(forward_ + sx * right_ + sy * up_), kInfinity};
    }
    return Ray{camera_.position + sx * right_ + sy * up_, forward_, kInfinity};
}

Ray CameraRays::generate(float x, float y, vec2 lens) const {
    Ray pinhole = generate(x, y);
    if (!thin_lens()) return pinhole;
    // The pinhole ray meets the plane of focus at t = focus / cos(angle to forward).
    vec3 focus_point = pinhole.o + pinhole.d * (focus_ / glm::dot(pinhole.d, forward_));
    vec2 disc = 0.5f * camera_.aperture * sample_disk_concentric(lens);
    vec3 origin = camera_.position + disc.x * right_ + disc.y * up_;
    return Ray{origin, glm::normalize(focus_point - origin), kInfinity};
}

}  // namespace svetlo
