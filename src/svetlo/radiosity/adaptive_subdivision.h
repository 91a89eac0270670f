// Adaptive subdivision (docs/radiosity.md): where the light that reaches an element straight
// from the lights and emitters changes fast across it, as at a shadow's edge, the element is
// split, up to render.radiosity.max_subdivision levels below the uniform mesh. This is what
// gives radiosity its soft shadows without a fine mesh everywhere.
#pragma once

#include <cstdint>

#include "svetlo/radiosity/patch_mesh.h"

namespace svetlo {

/// Splits every leaf whose direct irradiance, at its three corners and its centroid on
/// either side, spans more than settings.adaptive times its mean (or 1 % of the brightest
/// value, where that is larger); repeats on the children. Returns the shadow rays traced.
uint64_t subdivide_adaptive(PatchMesh& mesh, int samples, uint64_t seed, int threads);

}  // namespace svetlo
