#include "svetlo/raster/image_based_lighting.h"

#include <cmath>

#include "svetlo/raster/edge_function.h"

namespace svetlo {

std::array<float, 9> sh_basis(vec3 d) {
    return {0.282095f,
            0.488603f * d.y,
            0.488603f * d.z,
            0.488603f * d.x,
            1.092548f * d.x * d.y,
            1.092548f * d.y * d.z,
            0.315392f * (3.0f * d.z * d.z - 1.0f),
            1.092548f * d.x * d.z,
            0.546274f * (d.x * d.x - d.y * d.y)};
}

IblCache::Made make_image_based_lighting(const Scene& scene, int threads) {
    IblCache::Made made;
    const Environment environment(scene, false);
    // L_lm = integral of L Y_lm over the sphere, texel by texel: a texel of row j spans
    // (2 pi / W)(pi / H) cos(latitude) steradians; its radiance is read at its centre.
    const TextureImage& map = scene.textures[static_cast<size_t>(scene.environment->texture)];
    const int w = map.width(), h = map.height();
    std::array<glm::dvec3, 9> sum{};
    for (int j = 0; j < h; ++j) {
        const float v = 1.0f - (j + 0.5f) / h, lat = kPi * (v - 0.5f);
        const double solid_angle = (2.0 * kPi / w) * (kPi / h) * std::cos(lat);
        for (int i = 0; i < w; ++i) {
            const vec3 d = environment.direction_of(vec2((i + 0.5f) / w, v));
            const glm::dvec3 L(map.texel(i, j) * scene.environment->scale);
            const std::array<float, 9> y = sh_basis(d);
            for (int k = 0; k < 9; ++k) sum[static_cast<size_t>(k)] += L * (y[k] * solid_angle);
        }
    }
    const float a[9] = {kPi,     2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4,
                        kPi / 4, kPi / 4,     kPi / 4,     kPi / 4};
    for (int k = 0; k < 9; ++k)
        made.coefficients[static_cast<size_t>(k)] = Color(sum[static_cast<size_t>(k)]) * a[k];
    made.prefiltered = std::make_shared<const PrefilteredEnvironment>(environment, threads);
    made.table = std::make_shared<const SplitSumTable>(threads);
    return made;
}

IblCache::Made IblCache::of(const Scene& scene, int threads) {
    const EnvironmentSettings& e = *scene.environment;
    const TextureImage& map = scene.textures[static_cast<size_t>(e.texture)];
    const bool same = made_.prefiltered && kept_.environment &&
                      kept_.environment->rotate_deg == e.rotate_deg &&
                      kept_.environment->scale == e.scale && kept_.textures[0].same_texels(map);
    if (same) return made_;
    if (map.bytes() > kKeptBytes) {
        made_ = {};
        kept_ = {};
        return make_image_based_lighting(scene, threads);
    }
    // The copy is a scene of one texture, so that the prefiltered map's lookup (an
    // Environment, which points at its scene's texture) reads the copy, not this frame's.
    kept_.textures = {map};
    kept_.environment = e;
    kept_.environment->texture = 0;
    made_ = make_image_based_lighting(kept_, threads);
    return made_;
}

ImageBasedLighting::ImageBasedLighting(const Scene& scene, int threads, IblCache* cache)
    : environment_(scene, false) {
    if (!environment_.is_map()) return;
    made_ = cache ? cache->of(scene, threads) : make_image_based_lighting(scene, threads);
}

Color ImageBasedLighting::glossy(vec3 r, float n_dot_v, float roughness, Color f0,
                                 float f90) const {
    const vec2 ab = made_.table->at(n_dot_v, roughness);
    return made_.prefiltered->radiance(r, roughness) * (f0 * ab.x + Color(f90 * ab.y));
}

Color ImageBasedLighting::blurred(vec3 d, float roughness) const {
    return made_.prefiltered->radiance(d, roughness);
}

Color ImageBasedLighting::irradiance(vec3 n) const {
    const std::array<float, 9> y = sh_basis(n);
    Color E(0.0f);
    for (int k = 0; k < 9; ++k) E += made_.coefficients[static_cast<size_t>(k)] * y[k];
    return glm::max(E, Color(0.0f));  // order 2 can ring below zero behind a sun
}

FilmRays::FilmRays(const CameraMatrices& cam) : orthographic_(cam.orthographic) {
    if (orthographic_) {
        c_ = cam.forward;
        return;
    }
    const mat4 inverse = glm::inverse(cam.view_projection());
    // The ray through NDC (x, y): two points on it, in front of the camera, give its direction,
    // scaled to reach the plane one unit ahead of the eye (dot(p, forward) = 1), on which the
    // rays' points are affine in x and y.
    auto on_plane = [&](float x, float y) {
        auto unproject = [&](float z) {
            const vec4 p = inverse * vec4(x, y, z, 1.0f);
            return vec3(p) / p.w;
        };
        const vec3 d = glm::normalize(unproject(0.5f) - unproject(0.0f));
        return d / glm::dot(d, cam.forward);
    };
    const vec3 centre = on_plane(0.0f, 0.0f);
    const vec3 right = on_plane(1.0f, 0.0f) - centre, up = on_plane(0.0f, 1.0f) - centre;
    // NDC from pixels: x = 2 px / width - 1, y = 1 - 2 py / height.
    a_ = right * (2.0f / static_cast<float>(cam.width));
    b_ = up * (-2.0f / static_cast<float>(cam.height));
    c_ = centre - right + up;
}

}  // namespace svetlo
