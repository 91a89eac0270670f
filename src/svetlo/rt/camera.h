// Camera rays. The world is right-handed; as with gluLookAt, the image's right is
// forward x up and its top the part of `up` orthogonal to forward. Film coordinates (x, y)
// in [0,1]^2 run right and down from the top-left corner, so pixel (i, j) covers
// ((i, i+1)/W, (j, j+1)/H).
#pragma once

#include "svetlo/core/sampling.h"
#include "svetlo/geometry/ray.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

class CameraRays {
public:
    CameraRays(const Camera& camera, int width, int height);

    /// The ray through film point (x, y); the direction is unit length.
    Ray generate(float x, float y) const;
    /// The same through point `lens` in [0,1)^2 of a thin lens (camera.aperture > 0): it
    /// leaves a point of the lens's disc toward the point of the plane of focus that the
    /// pinhole ray meets (Kolb, Mitchell and Hanrahan 1995; pbrt-v4 section 5.2.3), so that
    /// only that plane is sharp.
    Ray generate(float x, float y, vec2 lens) const;
    bool thin_lens() const { return camera_.aperture > 0.0f; }

    vec3 forward() const { return forward_; }
    vec3 right() const { return right_; }
    vec3 up() const { return up_; }

private:
    Camera camera_;
    vec3 forward_, right_, up_;
    float half_w_, half_h_;  // tangents of the half-angles, or half extents (orthographic)
    float focus_ = 1.0f;     // the plane of focus's distance along forward
};

}  // namespace svetlo
