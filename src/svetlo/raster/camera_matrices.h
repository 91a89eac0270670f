// The vertex stage's matrices (OpenGL conventions, as a student meets them): model (object to
// world, the object's transform), view (world to camera, gluLookAt: the camera looks down -z,
// x is forward x up), projection (camera to clip space, gluPerspective or glOrtho: visible
// points have -w <= x, y, z <= w), and the viewport (normalised device coordinates to pixels,
// y down: pixel (i, j) covers [i, i+1] x [j, j+1]).
#pragma once

#include "svetlo/scene/scene.h"

namespace svetlo {

struct CameraMatrices {
    mat4 view{1.0f};
    mat4 projection{1.0f};
    float near = 0.1f, far = 100.0f;  // clip plane distances along the view direction
    int width = 1, height = 1;        // viewport in pixels
    vec3 eye{0.0f};                   // the camera's position, world space
    vec3 forward{0.0f, 0.0f, -1.0f};  // unit viewing direction, world space
    bool orthographic = false;

    mat4 view_projection() const { return projection * view; }
    /// Normalised device coordinates to pixels (x right, y down from the top-left corner).
    vec2 to_pixels(vec2 ndc) const {
        return vec2((ndc.x + 1.0f) * 0.5f * static_cast<float>(width),
                    (1.0f - ndc.y) * 0.5f * static_cast<float>(height));
    }
};

/// The camera's matrices for a width x height film. `far` encloses `bounds` (the scene's,
/// world space) with a margin. A perspective camera's projection has an infinite far plane,
/// and its near plane lies at half `nearest` when that is given (> 0): a lower bound on the
/// distance of anything visible, such as the distance from the eye to the nearest plane of a
/// triangle; else at half the bounds' distance in front. Near never depends on far (an object
/// a million units away must not clip the rest): the depth key -1/w is as precise at every
/// distance. Near is at least far / 10^9. Orthographic cameras clip to [near, far].
CameraMatrices camera_matrices(const Camera& camera, int width, int height, const Bounds3& bounds,
                               float nearest = 0.0f);

/// The distance from `eye` to the plane of triangle (a, b, c), or infinity when the triangle
/// lies wholly behind the eye (`forward`: the unit view direction): what bounds `nearest`.
inline float nearest_plane(vec3 a, vec3 b, vec3 c, vec3 eye, vec3 forward) {
    if (glm::dot(a - eye, forward) <= 0.0f && glm::dot(b - eye, forward) <= 0.0f &&
        glm::dot(c - eye, forward) <= 0.0f)
        return kInfinity;
    return std::abs(glm::dot(triangle_normal(a, b, c), eye - a));
}

/// The matrices of a pass jittered within the pixel: the image moves by (0.5, 0.5) - `jitter`
/// pixels, so that the centre of pixel (i, j) shows what the camera ray through (i + jitter.x,
/// j + jitter.y) sees. An item buffer drawn with them at one sample a pixel (at its centre)
/// matches that pass's rays.
CameraMatrices jittered_camera(const CameraMatrices& camera, vec2 jitter);

}  // namespace svetlo
