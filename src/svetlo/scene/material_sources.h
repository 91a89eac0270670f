// The colour sources of a material, asked one question at a time: whether any is textured,
// any needs mip chains, and so on. One list of which colours each material has, for every
// engine that must know (the rasterizer's per-material flags, the ray tracers' BSDF table).
#pragma once

#include <type_traits>
#include <variant>

#include "svetlo/scene/scene.h"

namespace svetlo {

/// True when f(colour source) holds for any colour source of m.
template <class F>
bool any_source(const Material& m, F&& f) {
    return std::visit(
        [&](const auto& mat) {
            using T = std::decay_t<decltype(mat)>;
            if constexpr (std::is_same_v<T, LambertMaterial> ||
                          std::is_same_v<T, OrenNayarMaterial>) {
                return f(mat.albedo);
            } else if constexpr (std::is_same_v<T, PhongMaterial>) {
                return f(mat.ka) || f(mat.kd) || f(mat.ks) || f(mat.reflect) || f(mat.transmit);
            } else if constexpr (std::is_same_v<T, CookTorranceMaterial>) {
                return f(mat.base_color);
            } else if constexpr (std::is_same_v<T, MirrorMaterial>) {
                return f(mat.reflectance);
            } else if constexpr (std::is_same_v<T, EmissiveMaterial>) {
                return f(mat.radiance) || f(mat.albedo);
            } else {
                return false;
            }
        },
        m);
}

/// A colour that varies over the surface (an image or a checker).
inline bool is_textured(const ColorSource& c) { return c.kind != ColorSource::Kind::Constant; }

}  // namespace svetlo
