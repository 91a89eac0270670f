// Intel Embree behind svetlo's Accel interface, the reference the hand-written structures are
// measured against. Triangles are Embree's own geometry (its BVH and SIMD triangle tests);
// analytic shapes are user geometry calling svetlo's intersectors; placements are Embree's own
// instances of one scene per prototype. Every hit is re-evaluated
// with svetlo's watertight triangle test so that shading sees the same t and barycentrics
// whichever structure found the primitive. Built only when CMake finds Embree 3.
#pragma once

#include <memory>

#include "svetlo/geometry/accel.h"

namespace svetlo {

/// True when this build has the Embree backend.
bool embree_available();

/// Embree over `geometry`'s bounded primitives and its placements, building on `threads` threads (0
/// = all). Throws std::runtime_error when Embree is not built in or fails.
std::unique_ptr<Accel> make_embree_accel(const Geometry& geometry, int threads);

}  // namespace svetlo
