// Geometry with its acceleration structure, built once and shared by every render of one
// command that has the same shapes: `svetlo compare` renders one scene under several
// techniques and a reference, `svetlo serve` renders it again at each slider's change
// (docs/compare.md, "One scene, one BVH").
#pragma once

#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

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

/// The last `capacity` entries built, by key. The key names all that the entry is made of
/// (Scene::geometry_key, the structure's name): equal keys, equal entries.
class AccelCache {
public:
    explicit AccelCache(size_t capacity = 4) : capacity_(capacity) {}

    /// The entry for `key`: made by `build` on the first request, then shared. Safe to call
    /// from several threads (one builds, the others wait).
    std::shared_ptr<const BuiltGeometry> get(const std::string& key,
                                             const std::function<void(BuiltGeometry&)>& build);

    /// How many entries `get` has built (a hit builds none).
    int builds() const;

private:
    size_t capacity_;
    mutable std::mutex mutex_;
    std::list<std::pair<std::string, std::shared_ptr<const BuiltGeometry>>>
        entries_;  // newest first
    int builds_ = 0;
};

/// cache->get(key, build), or a new entry made by `build` where there is no cache.
std::shared_ptr<const BuiltGeometry> built_geometry(
    AccelCache* cache, const std::string& key, const std::function<void(BuiltGeometry&)>& build);

}  // namespace svetlo
