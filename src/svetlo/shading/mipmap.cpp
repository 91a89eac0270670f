#include "svetlo/shading/mipmap.h"

#include <algorithm>
#include <cmath>

#include "svetlo/shading/texture.h"

namespace svetlo {

MipChain build_mip_chain(const Image& image) {
    MipChain chain;
    chain.levels.push_back(image);
    while (chain.levels.back().width > 1 || chain.levels.back().height > 1) {
        const Image& up = chain.levels.back();
        Image down(std::max(1, up.width / 2), std::max(1, up.height / 2));
        for (int j = 0; j < down.height; ++j) {
            for (int i = 0; i < down.width; ++i) {
                Color sum(0.0f);
                for (int dj = 0; dj < 2; ++dj) {
                    for (int di = 0; di < 2; ++di) {
                        sum += up.at(std::min(2 * i + di, up.width - 1),
                                     std::min(2 * j + dj, up.height - 1));
                    }
                }
                down.at(i, j) = 0.25f * sum;
            }
        }
        chain.levels.push_back(std::move(down));
    }
    return chain;
}

float mip_level(const MipChain& chain, vec2 duv_dx, vec2 duv_dy) {
    const Image& base = chain.levels[0];
    vec2 size(static_cast<float>(base.width), static_cast<float>(base.height));
    float rho = std::max(glm::length(duv_dx * size), glm::length(duv_dy * size));
    if (!(rho > 1.0f)) return 0.0f;  // magnified (or no footprint): the finest level
    return std::log2(rho);
}

Color sample_trilinear(const MipChain& chain, vec2 uv, float lod, TextureWrap wrap) {
    int last = static_cast<int>(chain.levels.size()) - 1;
    lod = std::clamp(lod, 0.0f, static_cast<float>(last));
    int l0 = static_cast<int>(std::floor(lod));
    int l1 = std::min(l0 + 1, last);
    float t = lod - static_cast<float>(l0);
    Color a = sample_bilinear(chain.levels[static_cast<size_t>(l0)], uv, wrap);
    if (t == 0.0f || l1 == l0) return a;
    return (1.0f - t) * a + t * sample_bilinear(chain.levels[static_cast<size_t>(l1)], uv, wrap);
}

}  // namespace svetlo
