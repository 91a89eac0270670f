// Normal mapping, one rule for every engine (docs/real-scenes.md, "Normal maps"): the texel
// of a tangent-space map bends the shading normal in the frame of the surface's tangent,
// bitangent and normal (glTF 2.0, "normalTexture"; the frame of MikkTSpace).
#pragma once

#include <vector>

#include "svetlo/scene/scene.h"
#include "svetlo/shading/texture.h"

namespace svetlo {

/// The shading normal that `map`'s linear texel `texel` gives a surface of unit shading normal
/// ns and geometric normal ng (both of its front side) with tangent `tangent` (xyz unit and
/// orthogonal to ns, w the bitangent's side; SurfaceHit::tangent). ns itself where the
/// tangent is zero or the texel gives no direction. The answer to a mapped normal that faces
/// away from the geometric one: it is bent back over the surface, to 0.01 of the way above
/// it (cos 89.4 degrees from the plane), so that no light from behind the surface lights it
/// and no camera ray sees a normal that faces away from the geometry's side.
vec3 mapped_normal(const NormalMap& map, Color texel, vec3 ns, vec3 ng, vec4 tangent);

/// The same, the map read at `at` in `textures` (the ray tracers).
inline vec3 mapped_normal(const NormalMap& map, const Varyings& at, vec3 ns, vec3 ng, vec4 tangent,
                          const std::vector<TextureImage>& textures) {
    if (!map.present() || tangent.w == 0.0f) return ns;
    return mapped_normal(map, eval_color(map.texture, at, textures), ns, ng, tangent);
}

/// The clear coat's own normal map, where `material` has a coat with one (else null).
inline const NormalMap* coat_normal_map(const Material& material) {
    const auto* ct = std::get_if<CookTorranceMaterial>(&material.model);
    return ct && ct->has_coat() && ct->clearcoat_normal.present() ? &ct->clearcoat_normal : nullptr;
}

/// The clear coat's own shading normal at a point of `material` whose interpolated normal is
/// ns (front side, before any map): its own map's (glTF's clearcoatNormalTexture, `texel` that
/// map's texel), or ns itself where it has none but the base has a map (glTF: the coat takes
/// no normal map of the base); zero where the coat simply takes the shading normal (no coat,
/// or no map on either).
inline vec3 coat_shading_normal(const Material& material, Color texel, vec3 ns, vec3 ng,
                                vec4 tangent) {
    const auto* ct = std::get_if<CookTorranceMaterial>(&material.model);
    if (!ct || !ct->has_coat()) return vec3(0.0f);
    if (const NormalMap* map = coat_normal_map(material))
        return tangent.w == 0.0f ? ns : mapped_normal(*map, texel, ns, ng, tangent);
    return material.normal_map.present() ? ns : vec3(0.0f);
}

/// The coat's map read at `at` in `textures` (the ray tracers), or nothing to read.
inline vec3 coat_shading_normal(const Material& material, const Varyings& at, vec3 ns, vec3 ng,
                                vec4 tangent, const std::vector<TextureImage>& textures) {
    const NormalMap* map = coat_normal_map(material);
    return coat_shading_normal(material, map ? eval_color(map->texture, at, textures) : Color(0.0f),
                               ns, ng, tangent);
}

}  // namespace svetlo
