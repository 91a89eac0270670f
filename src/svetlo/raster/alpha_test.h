// Alpha in the rasterizer's passes (docs/real-scenes.md, "Alpha"): the samples of a masked
// triangle whose coverage is below its cutoff are not drawn (OpenGL's alpha test, or a
// fragment shader's discard), in the colour pass, the shadow maps' depth passes and the planar
// projection; a blended one keeps each sample with probability equal to its coverage, a
// coin per sample (stochastic transparency, Enderton et al. 2010: order-independent, and
// resolved by the samples of a pixel). The rule is the ray tracers' (shading/cutouts.h).
#pragma once

#include <vector>

#include "svetlo/shading/cutouts.h"

namespace svetlo::raster {

class AlphaTest {
public:
    /// `materials` indexed as the triangle list's material ids.
    AlphaTest(const std::vector<Material>& materials, const std::vector<TextureImage>& textures)
        : materials_(materials), textures_(textures) {
        for (const Material& m : materials) {
            active_.push_back(m.alpha.active() ? 1 : 0);
            any_ = any_ || m.alpha.active();
        }
    }
    bool any() const { return any_; }
    /// Whether triangles of material m are tested (else every covered sample is drawn).
    bool active(uint32_t m) const { return m < active_.size() && active_[m]; }
    /// Whether the sample with varyings `at`, `key` naming it (pixel, sample and triangle: a
    /// blend's coin), is a hole.
    bool hole(uint32_t m, const Varyings& at, uint64_t key) const {
        return alpha_hole(materials_[m].alpha, at, blend_coin(key), textures_);
    }

private:
    const std::vector<Material>& materials_;
    const std::vector<TextureImage>& textures_;
    std::vector<char> active_;
    bool any_ = false;
};

}  // namespace svetlo::raster
