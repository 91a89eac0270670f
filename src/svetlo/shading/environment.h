// The light that comes from far away: the scene's `environment` map, or the uniform
// `render.background` (docs/scene-format.md, "environment"). Every engine asks it for the
// radiance of a ray that leaves the scene; the path tracer and Whitted also draw directions
// from it by importance, with their densities for multiple importance sampling.
//
// A unit direction d = (x, y, z), y up, turned by -rotate about +y into the map's frame, reads
// the map at u = 0.5 + atan2(x, -z) / 2pi, v = 0.5 + asin(y) / pi (v = 0 the bottom row),
// bilinear between texel centres, wrapping in u. The angles come from atan2_approx
// (core/math.h: within 3e-7 rad, a 2,000th of a 4096-texel map's texel).
//
// Importance sampling (pbrt-v4's ImageInfiniteLight, Pharr et al. 2023, 12.5.2): a piecewise-
// constant density over the texels, each texel's weight its luminance times sin(theta) (the
// solid angle a texel row spans), the luminance taken as the largest of the texel and its
// eight neighbours, which bounds what the bilinear lookup can return anywhere in the texel
// (so that no direction with radiance has density zero), plus 1e-3 of the mean (no texel
// has density zero). Drawn as a marginal over rows, then a conditional over the row's
// texels; the density per steradian is p(u, v) / (2 pi^2 cos(latitude)).
//
// A strategy that multiple importance sampling pairs with the BSDF's draws from a second
// density, the same weights less their mean over the sphere, clamped at zero (MIS
// compensation: Karlik et al., "MIS Compensation: Optimizing Sampling Techniques in Multiple
// Importance Sampling", SIGGRAPH Asia 2019; pbrt-v4's ImageInfiniteLight): where the map is
// dimmer than its mean the BSDF's draws do well, and the map's are spent where it is bright.
// A map with nothing above its mean (a uniform one) keeps the first density.
#pragma once

#include <vector>

#include "svetlo/core/math.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// Which of the map's densities sample() and pdf() use: its importance, or the compensated
/// one, for a strategy that MIS pairs with the BSDF's (zero where the map is dimmer than its
/// mean: never alone).
enum class EnvironmentDensity { Importance, Compensated };

/// A direction drawn from the environment: its radiance and density per steradian.
struct EnvironmentSample {
    vec3 wi{0.0f};
    Color radiance{0.0f};
    float pdf = 0.0f;
};

class Environment {
public:
    /// The scene's map, or its uniform background; `importance` false skips the sampling
    /// tables (sample() and pdf() are then not to be called).
    explicit Environment(const Scene& scene, bool importance = true);

    /// Whether a map is given (false: the uniform background).
    bool is_map() const { return map_ != nullptr; }
    /// Whether nothing comes from far away.
    bool is_black() const { return black_; }
    /// The uniform background's radiance (is_map false).
    Color uniform() const { return uniform_; }

    /// The radiance arriving along -d from far away (d a unit direction leaving the scene).
    Color radiance(vec3 d) const;
    /// radiance(d[k]) into out[k] for `count` directions, bit for bit, the angles of many at
    /// once (the rasterizer's background).
    void radiance_many(const vec3* d, size_t count, Color* out) const;
    /// The map's radiance at (u, v) = uv_of(d) (without a map the uniform one): for a caller that
    /// reads other maps of the same layout at the same place (the rasterizer's prefiltered levels).
    Color radiance_at(vec2 uv) const;

    /// A direction by importance (map only), u in [0,1)^2, from the density `which`.
    EnvironmentSample sample(vec2 u,
                             EnvironmentDensity which = EnvironmentDensity::Importance) const;
    /// The density per steradian with which sample(u, which) draws the unit direction d.
    float pdf(vec3 d, EnvironmentDensity which = EnvironmentDensity::Importance) const;

    /// The world direction that reads the map at (u, v) (rotate applied), unit.
    vec3 direction_of(vec2 uv) const;
    /// Where the unit direction d reads the map: the inverse of direction_of.
    vec2 uv_of(vec3 d) const;

private:
    /// Bilinear between the texels (i0, j0) and (i0 + 1, j0 + 1) of the map (columns wrapped,
    /// rows clamped), at (ax, ay) in [0, 1) past the first, times the scale.
    Color bilinear(int i0, int j0, float ax, float ay) const;

    /// A piecewise-constant density over the texels, from one weight per texel (rows from
    /// the top).
    struct Tables {
        std::vector<float> row_cdf;    // height + 1 entries, rows from the top
        std::vector<float> texel_cdf;  // height x (width + 1)
        std::vector<float> density;    // per texel: its probability x texel count (over [0,1]^2)
        Tables() = default;
        Tables(const std::vector<double>& weight, int width, int height);
    };
    const Tables& tables(EnvironmentDensity which) const {
        return which == EnvironmentDensity::Compensated ? compensated_ : importance_;
    }

    const TextureImage* map_ = nullptr;
    Color scale_{1.0f}, uniform_{0.0f};
    float cos_rot_ = 1.0f, sin_rot_ = 0.0f;
    bool black_ = true;
    int width_ = 0, height_ = 0;
    Tables importance_, compensated_;
};

}  // namespace svetlo
