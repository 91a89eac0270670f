// The colour sources of a material, asked one question at a time: whether any is textured,
// any needs mip chains, and so on. One list of which colours each material has, for every
// engine that must know (the rasterizer's per-material flags, the ray tracers' BSDF table).
#pragma once

#include <type_traits>
#include <variant>

#include "svetlo/scene/scene.h"

namespace svetlo {

/// True when f(colour source) holds for any colour source of m (Material or const Material;
/// an f that returns false visits them all).
template <class M, class F>
bool any_source(M& m, F&& f) {
    if (f(m.emission) || f(m.normal_map.texture) || f(m.alpha.coverage)) return true;
    return std::visit(
        [&](auto& mat) {
            using T = std::decay_t<decltype(mat)>;
            if constexpr (std::is_same_v<T, LambertMaterial> ||
                          std::is_same_v<T, OrenNayarMaterial>) {
                return f(mat.albedo);
            } else if constexpr (std::is_same_v<T, PhongMaterial>) {
                return f(mat.ka) || f(mat.kd) || f(mat.ks) || f(mat.reflect) || f(mat.transmit) ||
                       f(mat.shininess_map);
            } else if constexpr (std::is_same_v<T, CookTorranceMaterial>) {
                return f(mat.base_color) || f(mat.metallic_roughness) || f(mat.occlusion) ||
                       f(mat.transmission) || f(mat.clearcoat) || f(mat.clearcoat_roughness) ||
                       f(mat.clearcoat_normal.texture);
            } else if constexpr (std::is_same_v<T, MirrorMaterial>) {
                return f(mat.reflectance);
            } else if constexpr (std::is_same_v<T, EmissiveMaterial>) {
                return f(mat.radiance) || f(mat.albedo);
            } else {
                return false;
            }
        },
        m.model);
}

/// A colour that varies over the surface (an image, a checker, the vertex colour).
inline bool is_textured(const ColorSource& c) { return c.varies(); }
/// A colour read at the second texture coordinate set or times the vertex colour.
inline bool reads_more_than_uv(const ColorSource& c) {
    return c.uv_set != 0 || c.vertex_color != VertexColor::None;
}

/// True when the material gives off light: an emissive model's radiance or any model's
/// emission (what makes an object a light, light_set.h).
inline bool emits(const Material& m) {
    const auto* e = std::get_if<EmissiveMaterial>(&m.model);
    return (e && !e->radiance.is_black()) || !m.emission.is_black();
}

}  // namespace svetlo
