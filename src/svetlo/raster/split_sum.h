// Glossy image-based lighting as real-time renderers do it: the split-sum approximation
// (Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes). The specular
// integral of the environment L under the Cook-Torrance BRDF f is split into two factors,
//
//   integral L(l) f(v, l) cos dl  ~  [ sum L(l_k) cos_k / sum cos_k ]  x  [ integral f cos dl ],
//
// the first a prefiltered map (the environment averaged over GGX's lobe about the mirror
// direction r, taking n = v = r), the second the BRDF's directional albedo, which with
// Schlick's Fresnel is F0 A + B, A and B a table over (n.v, roughness). Both made once per
// map here, by importance sampling GGX with a fixed low-discrepancy set of directions.
// Exact for a uniform environment (the first factor is then the map itself); elsewhere the
// lobe's shape at grazing angles is what the n = v = r assumption gives up.
#pragma once

#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/shading/environment.h"

namespace svetlo {

/// The environment prefiltered for GGX at perceptual roughness 0, 1/4, 1/2, 3/4 and 1
/// (alpha = roughness^2); roughness 0 is the map itself.
class PrefilteredEnvironment {
public:
    /// Made on `threads` threads (0: all cores), a row of texels each: the same levels on any.
    explicit PrefilteredEnvironment(const Environment& environment, int threads = 0);
    /// The prefiltered radiance about the unit direction r at `roughness` in [0, 1], linear
    /// between the two levels around it.
    Color radiance(vec3 r, float roughness) const;

private:
    Color level_radiance(int level, vec2 uv) const;  // uv as Environment::uv_of

    Environment environment_;    // a copy (without its sampling tables): the map's lookup
    std::vector<Image> levels_;  // levels 1 to 4, equirectangular as the map
};

/// Karis' A and B over (n.v, roughness), 32 x 32, for svetlo's GGX (height-correlated Smith).
class SplitSumTable {
public:
    explicit SplitSumTable(int threads = 0);
    /// (A, B) at n.v in [0, 1] and perceptual roughness in [0, 1], bilinear.
    vec2 at(float n_dot_v, float roughness) const;

    static constexpr int kSize = 32;

private:
    std::vector<vec2> table_;  // row by roughness, column by n.v
};

/// A GGX half vector about +z for alpha, from u in [0, 1)^2 (the distribution D cos).
vec3 sample_ggx_half(vec2 u, float alpha);

}  // namespace svetlo
