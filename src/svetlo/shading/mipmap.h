// Mipmaps (Williams, "Pyramidal Parametrics", SIGGRAPH 1983): each level halves the one above
// with a 2x2 box filter, down to 1x1. A texture lookup with a screen-space footprint (the
// derivatives of uv across one pixel) picks the level whose texels match the footprint and
// blends the two nearest levels (trilinear filtering), or averages several such lookups
// along a stretched footprint (anisotropic filtering).
#pragma once

#include <vector>

#include "svetlo/core/texture_image.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// Level 0 is the texture itself (not copied: the chain must not outlive it); the smaller
/// levels are stored as the texture is (8-bit levels stay 8-bit, as glGenerateMipmap keeps
/// them), each averaged in linear RGB from the level above.
struct MipChain {
    const TextureImage* base = nullptr;
    std::vector<TextureImage> smaller;  // levels 1, 2, ... down to 1x1

    int count() const { return 1 + static_cast<int>(smaller.size()); }
    const TextureImage& level(int l) const {
        return l == 0 ? *base : smaller[static_cast<size_t>(l - 1)];
    }
};

/// The pyramid of `texture`. Odd sizes round down (the last row or column folds into the
/// level's last texel), so every level is at least 1x1.
MipChain build_mip_chain(const TextureImage& texture);
MipChain build_mip_chain(const TextureImage&& texture) = delete;  // it would dangle

/// Level of detail for a footprint: log2 of the longer of the two uv derivative vectors
/// measured in texels of level 0 (OpenGL 4.6 spec, section 8.14.1). Clamped at 0.
float mip_level(const MipChain& chain, vec2 duv_dx, vec2 duv_dy);

/// Bilinear lookups in the two levels around `lod`, blended linearly.
Color sample_trilinear(const MipChain& chain, vec2 uv, float lod, TextureWraps wrap);

/// Anisotropic filtering (in the manner of EXT_texture_filter_anisotropic): a footprint
/// longer in one direction than the other is covered by N = ceil(major / minor) trilinear
/// probes (at most max_probes), evenly spaced along the major axis, each at the level of
/// detail of major / N texels, and averaged; a round footprint is plain trilinear. Where
/// trilinear blurs a grazing texture to the level of its longer axis, this keeps the detail
/// of the shorter one.
Color sample_anisotropic(const MipChain& chain, vec2 uv, vec2 duv_dx, vec2 duv_dy, int max_probes,
                         TextureWraps wrap);

/// Where a texture lookup happens: its uv footprint across one pixel (zero without one, as
/// for rays) and the scene's mip chains (one per Scene::textures entry; empty for engines
/// that have no footprint).
struct TextureLookup {
    const std::vector<TextureImage>& images;
    const std::vector<MipChain>* mips = nullptr;
    vec2 duv_dx{0.0f}, duv_dy{0.0f};    // of texture coordinate set 0
    vec2 duv1_dx{0.0f}, duv1_dy{0.0f};  // of set 1 (Varyings::uv[1])
};

}  // namespace svetlo
