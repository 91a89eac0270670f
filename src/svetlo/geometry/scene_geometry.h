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

/// The scene's instances into `g`: each prototype an instance places built once, in its own
/// space, and one Placement per instance (geometry.h).
void place_instances(const Scene& scene, Geometry& g);

/// The placement of prototype `prototype` (of box `prototype_bounds` in its own space) by
/// `to_world`, its materials replaced by `material` where that is >= 0: the inverse, the
/// normals' matrix, whether it mirrors, and its box in the world, widened by a few ulps.
Placement make_placement(uint32_t prototype, const Transform& to_world, int material,
                         const Bounds3& prototype_bounds);

/// Pointers to every object of `objects`, then of `more` and `last` (for build_geometry).
std::vector<const Object*> object_pointers(const std::vector<Object>& objects,
                                           const std::vector<Object>& more = {},
                                           const std::vector<Object>& last = {});

}  // namespace svetlo
