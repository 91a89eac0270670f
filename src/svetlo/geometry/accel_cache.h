// Geometry with its acceleration structure, built once and shared by every render of one
// command that has the same shapes (core/shared_cache.h).
#pragma once

#include <memory>
#include <vector>

#include "svetlo/core/shared_cache.h"
#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/scene_geometry.h"

namespace svetlo {

/// A scene's world-space geometry and the structure over it. The structure refers to the
/// geometry, so an entry is built in place and never moved.
struct BuiltGeometry {
    Geometry geometry;
    std::vector<PrimitiveRange> ranges;  // per object, then per area light's quad
    std::unique_ptr<Accel> accel;
};

/// Built geometry by key: Scene::geometry_key and the structure's name.
class AccelCache : public SharedCache<BuiltGeometry> {
public:
    using SharedCache::SharedCache;
};

}  // namespace svetlo
