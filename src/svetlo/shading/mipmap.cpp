#include "svetlo/shading/mipmap.h"

#include <algorithm>
#include <cmath>

#include "svetlo/shading/texture.h"

namespace svetlo {

MipChain build_mip_chain(const TextureImage& texture) {
    MipChain chain;
    chain.base = &texture;
    while (chain.level(chain.count() - 1).width() > 1 ||
           chain.level(chain.count() - 1).height() > 1) {
        const TextureImage& up = chain.level(chain.count() - 1);
        TextureImage down = TextureImage::same_storage(up, std::max(1, up.width() / 2),
                                                       std::max(1, up.height() / 2));
        for (int j = 0; j < down.height(); ++j) {
            for (int i = 0; i < down.width(); ++i) {
                Color sum(0.0f);
                for (int dj = 0; dj < 2; ++dj) {
                    for (int di = 0; di < 2; ++di) {
                        sum += up.texel(std::min(2 * i + di, up.width() - 1),
                                        std::min(2 * j + dj, up.height() - 1));
                    }
                }
                down.set_texel(i, j, 0.25f * sum);
            }
        }
        chain.smaller.push_back(std::move(down));
    }
    return chain;
}

float mip_level(const MipChain& chain, vec2 duv_dx, vec2 duv_dy) {
    const TextureImage& base = chain.level(0);
    vec2 size(static_cast<float>(base.width()), static_cast<float>(base.height()));
    // The longer vector's length: one square root (sqrt is monotonic and correctly rounded,
    // so this is the larger of the two lengths exactly).
    const vec2 a = duv_dx * size, b = duv_dy * size;
    float rho = std::sqrt(std::max(glm::dot(a, a), glm::dot(b, b)));
    if (!(rho > 1.0f)) return 0.0f;  // magnified (or no footprint): the finest level
    return std::log2(rho);
}

Color sample_trilinear(const MipChain& chain, vec2 uv, float lod, TextureWraps wrap) {
    int last = chain.count() - 1;
    lod = std::clamp(lod, 0.0f, static_cast<float>(last));
    int l0 = static_cast<int>(std::floor(lod));
    int l1 = std::min(l0 + 1, last);
    float t = lod - static_cast<float>(l0);
    Color a = sample_bilinear(chain.level(l0), uv, wrap);
    if (t == 0.0f || l1 == l0) return a;
    return (1.0f - t) * a + t * sample_bilinear(chain.level(l1), uv, wrap);
}

Color sample_anisotropic(const MipChain& chain, vec2 uv, vec2 duv_dx, vec2 duv_dy, int max_probes,
                         TextureWraps wrap) {
    const TextureImage& base = chain.level(0);
    vec2 size(static_cast<float>(base.width()), static_cast<float>(base.height()));
    float px = glm::length(duv_dx * size), py = glm::length(duv_dy * size);  // texels
    float major = std::max(px, py), minor = std::min(px, py);
    if (!(major > 0.0f)) return sample_trilinear(chain, uv, 0.0f, wrap);  // no footprint
    // Probes: enough that each covers about the minor extent (a degenerate footprint, a
    // line, takes the most).
    float ratio = minor > 0.0f ? major / minor : static_cast<float>(max_probes);
    int n = std::clamp(static_cast<int>(std::ceil(ratio - 1e-4f)), 1, max_probes);
    float rho = major / static_cast<float>(n);
    float lod = rho > 1.0f ? std::log2(rho) : 0.0f;
    if (n == 1) return sample_trilinear(chain, uv, lod, wrap);
    vec2 axis = px >= py ? duv_dx : duv_dy;  // the major axis, in uv across one pixel
    Color sum(0.0f);
    for (int k = 0; k < n; ++k) {
        // Probe centres at the middles of n equal parts of the footprint's major axis.
        float t = (static_cast<float>(k) + 0.5f) / static_cast<float>(n) - 0.5f;
        sum += sample_trilinear(chain, uv + t * axis, lod, wrap);
    }
    return sum / static_cast<float>(n);
}

}  // namespace svetlo
