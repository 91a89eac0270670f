// The rasterizer's triangle lists, built once and shared by every render of one command that
// has the same shapes and tessellation (core/shared_cache.h): a drag in `svetlo serve` moves
// the camera only, and tessellating the scene's shapes again each frame would cost more than
// drawing them.
#pragma once

#include "svetlo/core/shared_cache.h"
#include "svetlo/geometry/triangle_list.h"

namespace svetlo {

/// Triangle lists by key: Scene::geometry_key and what else the list is made with.
class TriangleListCache : public SharedCache<TriangleList> {
public:
    using SharedCache::SharedCache;
};

}  // namespace svetlo
