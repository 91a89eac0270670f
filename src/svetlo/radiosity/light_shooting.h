// Light that reaches a surface point straight from the light set (shading/light_set.h), with
// shadow rays through the patch mesh's own triangles: how point, spot and directional lights
// shoot onto the elements before the solve, what adaptive subdivision compares, what the
// gather display adds exactly per pixel, and the visibility AOV of light 0.
#pragma once

#include <cstdint>

#include "svetlo/core/rng.h"
#include "svetlo/geometry/accel.h"
#include "svetlo/shading/environment.h"
#include "svetlo/shading/light_set.h"

namespace svetlo {

enum class LightSources { Delta, All };

/// The irradiance (W/m^2) at x on the side of unit normal n: every delta light once, every
/// light with area by `samples` stratified points (LightSources::All only), each times its
/// visibility. Adds its rays to `rays`.
Color light_irradiance(const LightSet& lights, const Accel& accel, vec3 x, vec3 n,
                       LightSources which, int samples, Rng& rng, uint64_t& rays);

/// The irradiance (W/m^2) at x on the side of unit normal n from far away. The uniform
/// background: pi L_bg times the cosine-weighted fraction of the hemisphere that is open, by
/// `rays` stratified rays; a map: 4 x `rays` directions by its importance, L cos / pdf for
/// those that reach it.
Color sky_irradiance(const Accel& accel, const Environment& environment, vec3 x, vec3 n, int rays,
                     Rng& rng);

/// The fraction of light 0 that reaches x (n facing the viewer): 0 or 1 for a delta light,
/// the free fraction of max(samples, 16) stratified points for a light with area, 1 where x
/// faces away from it or there is no light 0 (docs/shading.md, "Radiometric conventions").
float light0_visibility(const LightSet& lights, const Accel& accel, vec3 x, vec3 n, int samples,
                        Rng& rng, uint64_t& rays);

}  // namespace svetlo
