// The camera's rays through the film (image_based_lighting.h, FilmRays), which the background
// of the map is read along, against the pinhole camera's closed form: through the pixel point
// (px, py) of a W x H film, the direction forward + (2 px / W - 1) tan(fov/2) (W/H) right +
// (1 - 2 py / H) tan(fov/2) up, normalised.
#include <gtest/gtest.h>

#include <cmath>

#include "svetlo/raster/image_based_lighting.h"

namespace svetlo {
namespace {

TEST(FilmRays, APerspectiveCamerasRaysAreThePinholes) {
    Camera c;
    c.position = vec3(1.3f, 2.0f, 4.0f);
    c.look_at = vec3(0.2f, -0.1f, 0.0f);
    c.fov_deg = 55.0f;
    const int w = 64, h = 36;
    const CameraMatrices cam = camera_matrices(c, w, h, Bounds3{vec3(-1.0f), vec3(1.0f)});
    const FilmRays rays(cam);
    const vec3 forward = glm::normalize(c.look_at - c.position);
    const vec3 right = glm::normalize(glm::cross(forward, c.up));
    const vec3 up = glm::cross(right, forward);
    const float t = std::tan(glm::radians(c.fov_deg) / 2.0f);
    // Corners, the centre, and points between pixels (sample positions are in 1/kSubpixel).
    for (auto [sx, sy] : {std::pair<int64_t, int64_t>{0, 0},
                          {w * kSubpixel, 0},
                          {0, h * kSubpixel},
                          {w * kSubpixel, h * kSubpixel},
                          {w * kSubpixel / 2, h * kSubpixel / 2},
                          {17 * kSubpixel + 37, 29 * kSubpixel + 201}}) {
        const float px = static_cast<float>(sx) / kSubpixel,
                    py = static_cast<float>(sy) / kSubpixel;
        const vec3 expected = glm::normalize(forward + (2.0f * px / w - 1.0f) * t * w / h * right +
                                             (1.0f - 2.0f * py / h) * t * up);
        const vec3 d = rays.direction(sx, sy);
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(d[a], expected[a], 2e-6f) << sx << ", " << sy;
    }
}

TEST(FilmRays, AnOrthographicCamerasRaysAllLookForward) {
    Camera c;
    c.type = Camera::Type::Orthographic;
    c.position = vec3(0.0f, 3.0f, 3.0f);
    c.look_at = vec3(0.0f);
    const CameraMatrices cam = camera_matrices(c, 40, 30, Bounds3{vec3(-1.0f), vec3(1.0f)});
    const FilmRays rays(cam);
    const vec3 forward = glm::normalize(c.look_at - c.position);
    for (int64_t s : {int64_t{0}, int64_t{5 * kSubpixel + 3}, int64_t{40 * kSubpixel}}) {
        const vec3 d = rays.direction(s, s / 2);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(d[a], forward[a], 1e-6f);
    }
}

}  // namespace
}  // namespace svetlo
