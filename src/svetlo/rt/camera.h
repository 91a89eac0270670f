// Camera rays. The world is right-handed; as with gluLookAt, the image's right is
// forward x up and its top the part of `up` orthogonal to forward. Film coordinates (x, y)
// in [0,1]^2 run right and down from the top-left corner, so pixel (i, j) covers
// ((i, i+1)/W, (j, j+1)/H).
#pragma once

#include "svetlo/geometry/ray.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

class CameraRays {
public:
    CameraRays(const Camera& camera, int width, int height);

    /// The ray through film point (x, y); the direction is unit length.
    Ray generate(float x, float y) const;

    vec3 forward() const { return forward_; }
    vec3 right() const { return right_; }
    vec3 up() const { return up_; }

private:
    Camera camera_;
    vec3 forward_, right_, up_;
    float half_w_, half_h_;  // tangents of the half-angles, or half extents (orthographic)
};

}  // namespace svetlo
