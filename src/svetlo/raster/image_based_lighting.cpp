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

ImageBasedLighting::ImageBasedLighting(const Scene& scene, int threads)
    : environment_(scene, false) {
    if (!environment_.is_map()) return;
    // L_lm = integral of L Y_lm over the sphere, texel by texel: a texel of row j spans
    // (2 pi / W)(pi / H) cos(latitude) steradians; its radiance is read at its centre.
    const TextureImage& map = scene.textures[static_cast<size_t>(scene.environment->texture)];
    const int w = map.width(), h = map.height();
    std::array<glm::dvec3, 9> sum{};
    for (int j = 0; j < h; ++j) {
        const float v = 1.0f - (j + 0.5f) / h, lat = kPi * (v - 0.5f);
        const double solid_angle = (2.0 * kPi / w) * (kPi / h) * std::cos(lat);
        for (int i = 0; i < w; ++i) {
            const vec3 d = environment_.direction_of(vec2((i + 0.5f) / w, v));
            const glm::dvec3 L(map.texel(i, j) * scene.environment->scale);
            const std::array<float, 9> y = sh_basis(d);
            for (int k = 0; k < 9; ++k) sum[static_cast<size_t>(k)] += L * (y[k] * solid_angle);
        }
    }
    const float a[9] = {kPi,     2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4,
                        kPi / 4, kPi / 4,     kPi / 4,     kPi / 4};
    for (int k = 0; k < 9; ++k)
        coefficients_[static_cast<size_t>(k)] = Color(sum[static_cast<size_t>(k)]) * a[k];
    prefiltered_.emplace(environment_, threads);
    table_.emplace(threads);
}

Color ImageBasedLighting::glossy(vec3 r, float n_dot_v, float roughness, Color f0) const {
    const vec2 ab = table_->at(n_dot_v, roughness);
    return prefiltered_->radiance(r, roughness) * (f0 * ab.x + Color(ab.y));
}

Color ImageBasedLighting::irradiance(vec3 n) const {
    const std::array<float, 9> y = sh_basis(n);
    Color E(0.0f);
    for (int k = 0; k < 9; ++k) E += coefficients_[static_cast<size_t>(k)] * y[k];
    return glm::max(E, Color(0.0f));  // order 2 can ring below zero behind a sun
}

Color ImageBasedLighting::seen(const CameraMatrices& cam, const mat4& inverse, int64_t sx,
                               int64_t sy) const {
    const float px = static_cast<float>(sx) / kSubpixel, py = static_cast<float>(sy) / kSubpixel;
    const vec2 ndc(2.0f * px / cam.width - 1.0f, 1.0f - 2.0f * py / cam.height);
    // Two points on the sample's ray, in front of the camera: their difference is its direction.
    auto unproject = [&](float z) {
        const vec4 p = inverse * vec4(ndc, z, 1.0f);
        return vec3(p) / p.w;
    };
    const vec3 d =
        cam.orthographic ? cam.forward : glm::normalize(unproject(0.5f) - unproject(0.0f));
    return environment_.radiance(d);
}

}  // namespace svetlo
