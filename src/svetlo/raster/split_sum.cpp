#include "svetlo/raster/split_sum.h"

#include <algorithm>
#include <cmath>

#include "svetlo/core/parallel.h"
#include "svetlo/core/sampling.h"

namespace svetlo {

namespace {

constexpr int kLevels = 5;  // roughness 0, 1/4, 1/2, 3/4, 1

float alpha_of(float roughness) { return std::max(roughness * roughness, 1e-3f); }

/// Bilinear between texel centres of an equirectangular image (rows from the top, v = 0 the
/// bottom row): wrapping in u, clamped in v.
Color equirect_lookup(const Image& im, vec2 uv) {
    const float x = uv.x * static_cast<float>(im.width) - 0.5f;
    const float y = (1.0f - uv.y) * static_cast<float>(im.height) - 0.5f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    auto texel = [&](int i, int j) {
        i = ((i % im.width) + im.width) % im.width;
        j = std::clamp(j, 0, im.height - 1);
        return im.at(i, j);
    };
    const int i = static_cast<int>(x0), j = static_cast<int>(y0);
    return (1.0f - fx) * (1.0f - fy) * texel(i, j) + fx * (1.0f - fy) * texel(i + 1, j) +
           (1.0f - fx) * fy * texel(i, j + 1) + fx * fy * texel(i + 1, j + 1);
}

}  // namespace

vec3 sample_ggx_half(vec2 u, float alpha) {
    const float a2 = alpha * alpha;
    const float cos_t = std::sqrt((1.0f - u.x) / (1.0f + (a2 - 1.0f) * u.x));
    const float sin_t = safe_sqrt(1.0f - cos_t * cos_t), phi = 2.0f * kPi * u.y;
    return vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
}

PrefilteredEnvironment::PrefilteredEnvironment(const Environment& environment, int threads)
    : environment_(environment) {
    if (!environment.is_map()) return;
    for (int level = 1; level < kLevels; ++level) {
        // Finer where the lobe is narrow: about two texels across its half width.
        const int h = level == 1 ? 64 : 32, w = 2 * h, samples = 64;
        const float alpha = alpha_of(static_cast<float>(level) / (kLevels - 1));
        Image im(w, h);
        parallel_indices(static_cast<size_t>(h), threads, [&](size_t row) {
            const int j = static_cast<int>(row);
            for (int i = 0; i < w; ++i) {
                const vec3 r = environment.direction_of(vec2(
                    (static_cast<float>(i) + 0.5f) / w, 1.0f - (static_cast<float>(j) + 0.5f) / h));
                const Frame frame = Frame::from_normal(r);
                Color sum(0.0f);
                float weight = 0.0f;
                for (int k = 0; k < samples; ++k) {
                    const vec3 half = frame.to_world(sample_ggx_half(r2_sequence(k), alpha));
                    const vec3 l = 2.0f * glm::dot(r, half) * half - r;
                    const float cos_l = glm::dot(r, l);
                    if (cos_l <= 0.0f) continue;
                    sum += environment.radiance(l) * cos_l;
                    weight += cos_l;
                }
                im.at(i, j) = weight > 0.0f ? sum / weight : Color(0.0f);
            }
        });
        levels_.push_back(std::move(im));
    }
}

Color PrefilteredEnvironment::level_radiance(int level, vec2 uv) const {
    if (level == 0) return environment_.radiance_at(uv);
    return equirect_lookup(levels_[static_cast<size_t>(level - 1)], uv);
}

Color PrefilteredEnvironment::radiance(vec3 r, float roughness) const {
    const float t = std::clamp(roughness, 0.0f, 1.0f) * (kLevels - 1);
    const int lo = std::min(static_cast<int>(t), kLevels - 2);
    const float f = t - static_cast<float>(lo);
    const vec2 uv = environment_.uv_of(r);  // one place in every level
    if (f <= 0.0f) return level_radiance(lo, uv);
    return (1.0f - f) * level_radiance(lo, uv) + f * level_radiance(lo + 1, uv);
}

SplitSumTable::SplitSumTable(int threads) : table_(kSize * kSize) {
    constexpr int kSamples = 256;
    parallel_indices(kSize, threads, [&](size_t r) {
        const int row = static_cast<int>(r);
        const float alpha = alpha_of(static_cast<float>(row) / (kSize - 1));
        const float a2 = alpha * alpha;
        for (int col = 0; col < kSize; ++col) {
            // n.v from just above 0 to 1 (0 itself has no view direction).
            const float cos_v = std::max(static_cast<float>(col) / (kSize - 1), 1e-3f);
            const vec3 v(safe_sqrt(1.0f - cos_v * cos_v), 0.0f, cos_v);
            float a = 0.0f, b = 0.0f;
            for (int k = 0; k < kSamples; ++k) {
                const vec3 h = sample_ggx_half(r2_sequence(k), alpha);
                const float vh = glm::dot(v, h);
                const vec3 l = 2.0f * vh * h - v;
                if (l.z <= 0.0f || vh <= 0.0f) continue;
                // f cos / pdf = F V 4 (n.l) (v.h) / (n.h), pdf = D (n.h) / (4 v.h), with the
                // height-correlated Smith visibility V of bsdf.cpp.
                const float vis = 0.5f / (l.z * std::sqrt(cos_v * cos_v * (1.0f - a2) + a2) +
                                          cos_v * std::sqrt(l.z * l.z * (1.0f - a2) + a2));
                const float w = vis * 4.0f * l.z * vh / h.z;
                const float fc = std::pow(1.0f - vh, 5.0f);
                a += (1.0f - fc) * w;
                b += fc * w;
            }
            table_[static_cast<size_t>(row * kSize + col)] =
                vec2(a, b) / static_cast<float>(kSamples);
        }
    });
}

vec2 SplitSumTable::at(float n_dot_v, float roughness) const {
    const float x = std::clamp(n_dot_v, 0.0f, 1.0f) * (kSize - 1);
    const float y = std::clamp(roughness, 0.0f, 1.0f) * (kSize - 1);
    const int x0 = std::min(static_cast<int>(x), kSize - 2),
              y0 = std::min(static_cast<int>(y), kSize - 2);
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    auto t = [&](int i, int j) { return table_[static_cast<size_t>(j * kSize + i)]; };
    return (1.0f - fx) * (1.0f - fy) * t(x0, y0) + fx * (1.0f - fy) * t(x0 + 1, y0) +
           (1.0f - fx) * fy * t(x0, y0 + 1) + fx * fy * t(x0 + 1, y0 + 1);
}

}  // namespace svetlo
