// A scene's objects as world-space geometry, transforms baked in: what the ray tracer
// intersects and what the light set samples. Primitive ids follow Geometry's rule: the
// triangles of every mesh first, then one analytic shape per other object, each in object order.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/geometry/geometry.h"

namespace svetlo {

/// Builds the geometry of `objects`; `ranges`, when given, receives one range per object.
Geometry build_geometry(const std::vector<const Object*>& objects,
                        std::vector<PrimitiveRange>* ranges = nullptr);

/// Pointers to every object of `objects`, then of `more` (for build_geometry).
std::vector<const Object*> object_pointers(const std::vector<Object>& objects,
                                           const std::vector<Object>& more = {});

}  // namespace svetlo
