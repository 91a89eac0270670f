#include "svetlo/raster/camera_matrices.h"

#include <algorithm>

namespace svetlo {

CameraMatrices camera_matrices(const Camera& camera, int width, int height, const Bounds3& bounds,
                               float nearest) {
    CameraMatrices m;
    m.width = width;
    m.height = height;
    m.view = glm::lookAt(camera.position, camera.look_at, camera.up);
    m.eye = camera.position;
    m.forward = glm::normalize(camera.look_at - camera.position);
    m.orthographic = camera.type == Camera::Type::Orthographic;
    // Depth range of the scene in front of the camera: -z in view space of the bounds' corners.
    float zmin = kInfinity, zmax = -kInfinity;
    bool finite = std::isfinite(bounds.min.x + bounds.min.y + bounds.min.z + bounds.max.x +
                                bounds.max.y + bounds.max.z);
    if (finite && bounds.min.x <= bounds.max.x) {
        for (int k = 0; k < 8; ++k) {
            vec3 c((k & 1) ? bounds.max.x : bounds.min.x, (k & 2) ? bounds.max.y : bounds.min.y,
                   (k & 4) ? bounds.max.z : bounds.min.z);
            float z = -(m.view * vec4(c, 1.0f)).z;
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
    } else {
        zmin = 0.0f;
        zmax = 1.0f;
    }
    float aspect = static_cast<float>(width) / static_cast<float>(height);
    float margin = 0.01f * std::max(zmax - zmin, 1e-3f);
    m.far = std::max(zmax + margin, 1e-3f);
    if (camera.type == Camera::Type::Perspective) {
        float in_front = nearest > 0.0f ? 0.5f * nearest : zmin > 0.0f ? 0.5f * zmin : 0.0f;
        m.near = std::max(in_front, m.far * 1e-9f);
        // An infinite far plane: nothing is clipped behind, however far, and near may be
        // small (the depth key is -1/w, whose precision is relative at every distance).
        m.projection = glm::infinitePerspective(radians(camera.fov_deg), aspect, m.near);
    } else {
        m.near = std::max(zmin - margin, 0.0f);  // as the ray tracer: what lies in front only
        float h = 0.5f * camera.height, w = h * aspect;
        m.projection = glm::ortho(-w, w, -h, h, m.near, m.far);
    }
    return m;
}

CameraMatrices jittered_camera(const CameraMatrices& camera, vec2 jitter) {
    // to_pixels: a shift of d in normalised device coordinates moves x by d.x width / 2
    // pixels and y by -d.y height / 2 (pixels count down).
    const vec2 shift(0.5f - jitter.x, 0.5f - jitter.y);
    const vec2 d(2.0f * shift.x / static_cast<float>(camera.width),
                 -2.0f * shift.y / static_cast<float>(camera.height));
    CameraMatrices m = camera;
    m.projection = glm::translate(mat4(1.0f), vec3(d, 0.0f)) * camera.projection;
    return m;
}

}  // namespace svetlo
