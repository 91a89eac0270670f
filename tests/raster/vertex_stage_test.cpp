// The rasterizer's stages 1 to 3: the camera matrices against the camera rays, and clipping.
#include "raster_testing.h"

namespace svetlo {
namespace {

using namespace raster_testing;

TEST(Raster, ClippingKeepsThePartInFrontOfTheNearPlane) {
    ClipVertex a, b, c;
    a.clip = vec4(0, 0, -2, 1);  // in front of the near plane (z < -w would be behind)
    b.clip = vec4(1, 0, -3, 1);  // behind it
    c.clip = vec4(0, 1, 0.5f, 1);
    a.uv = vec2(0, 0);
    b.uv = vec2(1, 0);
    c.uv = vec2(0, 1);
    ClipPolygon p = clip_triangle(a, b, c, 2.0f, 2.0f);
    ASSERT_EQ(p.count, 3);  // one vertex kept, two made on the near plane
    for (int k = 0; k < p.count; ++k) {
        const ClipVertex& v = p.v[static_cast<size_t>(k)];
        EXPECT_GE(v.clip.z, -v.clip.w - 1e-6f);
        EXPECT_LE(v.clip.z, v.clip.w + 1e-6f);
        // Attributes follow the clip-space position linearly: uv.y tracks y here.
        EXPECT_NEAR(v.uv.y, v.clip.y, 1e-6f);
    }
    ClipPolygon none = clip_triangle(b, b, b, 2.0f, 2.0f);
    EXPECT_EQ(none.count, 0);
}

// Found by tests/fuzz/mutate_scenes.py: a sphere of radius 3.4e38 gave a vertex y = -inf with
// a finite w, inside the clip volume because g w overflowed to inf; it was snapped to INT_MIN,
// and the triangle's bounds overflowed a signed integer (under UBSan).
TEST(Raster, AVertexThatCannotBeProjectedIsNotInside) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(inside(vec4(0.5f, -0.5f, 0.0f, 1.0f), 2.0f, 2.0f));
    EXPECT_TRUE(inside(vec4(0.0f, 0.0f, 0.0f, std::numeric_limits<float>::min()), 2.0f, 2.0f));
    EXPECT_FALSE(inside(vec4(inf, 0.0f, 0.0f, inf), 2.0f, 2.0f));      // overflowed
    EXPECT_FALSE(inside(vec4(0.0f, 0.0f, 0.0f, inf), 2.0f, 2.0f));     // 0 / inf: nothing
    EXPECT_FALSE(inside(vec4(0.0f, 0.0f, 0.0f, 1e-40f), 2.0f, 2.0f));  // 1 / w = inf
    EXPECT_FALSE(inside(vec4(0.0f, 0.0f, 0.0f, 0.0f), 2.0f, 2.0f));
    // The fuzzer's vertex: y overflowed, w did not, and g w does.
    EXPECT_FALSE(inside(vec4(4.79f, -inf, 1.8e38f, 1.8e38f), 8193.0f, 8193.0f));
    // The sphere itself, in every shading mode and on films down to one pixel: every value
    // finite (and, under UBSan, no overflow on the way).
    for (const char* shading : {"flat", "gouraud", "phong"}) {
        for (int size : {1, 3, 24}) {
            json j = oblique(size, size);
            j["render"]["shading"] = shading;
            j["materials"] = {{"grey", {{"type", "lambert"}, {"albedo", 0.5}}}};
            j["lights"] = {
                {{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", {1, 1, 1}}}};
            j["objects"] = {{{"type", "sphere"},
                             {"center", {2.25, 0.6, 0}},
                             {"radius", 3.4e38},
                             {"material", "grey"}}};
            RenderResult r = render(j);
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) EXPECT_TRUE(is_finite(r.color.at(x, y)));
        }
    }
}

/// A camera looking obliquely at the origin, for the matrices' tests.
Camera oblique_camera(Camera::Type type) {
    Camera cam;
    cam.type = type;
    cam.position = vec3(1, 2, 3);
    cam.look_at = vec3(0, 0.5f, 0);
    cam.fov_deg = 45.0f;
    return cam;
}

TEST(Raster, MatricesProjectWhereTheCameraRaysGo) {
    for (auto type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        const Camera cam = oblique_camera(type);
        CameraMatrices m = camera_matrices(cam, 200, 100, Bounds3{vec3(-2), vec3(2)});
        for (vec2 film : {vec2(0.1f, 0.2f), vec2(0.5f, 0.5f), vec2(0.9f, 0.7f)}) {
            Ray r = contract_camera_ray(cam, 200, 100, film.x, film.y);
            vec3 p = r.o + 2.5f * r.d;
            vec4 clip = m.view_projection() * vec4(p, 1.0f);
            vec2 px = m.to_pixels(vec2(clip) / clip.w);
            EXPECT_NEAR(px.x, film.x * 200.0f, 1e-3f);
            EXPECT_NEAR(px.y, film.y * 100.0f, 1e-3f);
        }
    }
}

TEST(Raster, AJitteredCameraShowsTheJitteredRayAtThePixelCentre) {
    for (auto type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        const Camera cam = oblique_camera(type);
        for (int w : {1, 3, 200}) {
            const int h = w == 200 ? 100 : w;
            const CameraMatrices m = camera_matrices(cam, w, h, Bounds3{vec3(-2), vec3(2)});
            for (vec2 jitter : {vec2(0.5f), vec2(0.1f, 0.8f), vec2(0.95f, 0.05f)}) {
                const CameraMatrices jm = jittered_camera(m, jitter);
                const int i = w / 2, j = h / 3;
                Ray r = contract_camera_ray(cam, w, h, (static_cast<float>(i) + jitter.x) / w,
                                            (static_cast<float>(j) + jitter.y) / h);
                vec3 p = r.o + 2.5f * r.d;
                vec4 clip = jm.view_projection() * vec4(p, 1.0f);
                vec2 px = jm.to_pixels(vec2(clip) / clip.w);
                EXPECT_NEAR(px.x, static_cast<float>(i) + 0.5f, 1e-3f) << w << " " << jitter.x;
                EXPECT_NEAR(px.y, static_cast<float>(j) + 0.5f, 1e-3f) << h << " " << jitter.y;
            }
        }
    }
}

}  // namespace
}  // namespace svetlo
