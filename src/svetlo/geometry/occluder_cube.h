// The nearest occluders around one point E, by direction: a cube map centred on E whose every
// cell keeps how near to E the triangles whose projection may cover the cell come, along the
// cell's directions. A shadow ray from o toward E (the segment o -> E) can meet a triangle
// only at a point in the direction of o - E and nearer to E than o; where every triangle the
// cell of o - E may hold lies farther from E than o, the segment is clear without being
// traced. The rasterizer's shadow rays toward a point are culled so (docs/geometry.md,
// "Shadow rays culled by a cube of occluders").
//
// Conservative by construction: each triangle enters every cell its projection may touch
// (the bounding rectangle of its projected corners, one cell wider each way) with a lower
// bound of its distance to E along the cell's directions, so that `clear` never answers true
// for a segment a triangle blocks, whatever the rounding of the ray test or of the shadow
// ray's origin.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/core/shared_cache.h"
#include "svetlo/geometry/triangle_list.h"

namespace svetlo {

class OccluderCube {
public:
    /// Cells per side of each of the six faces: 0.7 degrees a cell at a face's centre.
    static constexpr int kResolution = 128;

    OccluderCube() = default;
    /// Over the triangles of `list` (whose vertices all have weight 1), around `end`, built
    /// face by face on `threads` threads; the cube does not depend on their number.
    OccluderCube(const TriangleList& list, vec3 end, int threads);

    /// Whether the shadow ray toward the end of a sample at p, on triangle `triangle` of the
    /// list and its side of unit normal n, is known to meet nothing: the ray that leaves from
    /// a hair off p (offset_ray_origin, as the rasterizer's shadow rays do), and that cannot
    /// meet the sample's own object when it leaves it (leaves_convex). False when something
    /// may block it (it must then be traced), when p is nearer the end than a sixteenth of the
    /// scene's scale (the hair could change its cell), or is not finite.
    bool clear(vec3 p, vec3 n, uint32_t triangle) const {
        const vec3 v = p - end_;
        const float length2 = glm::dot(v, v);
        if (!(length2 >= near2_ && length2 <= kLargest)) return false;
        const vec3 a = glm::abs(v);
        const int axis = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
        const float inv = 1.0f / a[axis];
        const int face = 2 * axis + (v[axis] < 0.0f ? 1 : 0);
        const int i = cell_index(v[(axis + 1) % 3] * inv), j = cell_index(v[(axis + 2) % 3] * inv);
        const Cell& c = cells_[(static_cast<size_t>(face) * kResolution + j) * kResolution + i];
        // The nearest object's own triangles do not count for a ray that leaves it.
        bool own = false;
        if (c.object < objects_.size()) {
            const PrimitiveRange& r = objects_[c.object];
            own = triangle >= r.first && triangle < r.end &&
                  leaves_convex(convex_[c.object] != 0, centroid_[c.object], p, n);
        }
        const float reach = std::sqrt(length2) + slack_;  // the origin's hair included
        return (own ? c.other2 : c.nearest2) > reach * reach;
    }

    /// The cells where no triangle comes (for the tests and the docs): a count.
    size_t empty_cells() const;

private:
    static constexpr float kLargest = 1.0e30f;
    static constexpr uint32_t kNoObject = ~0u;
    /// The least lower bound of distance to E of the triangles in the cell, squared, and the
    /// object (index into the list's objects) of the triangle that has it; the least among the
    /// triangles of the other objects, squared.
    struct Cell {
        float nearest2, other2;
        uint32_t object;
    };
    /// Triangle p (its corners relative to E, its distance d to E or 0 where not known, its
    /// object o) into the cells of `face` its projection may touch, each cell's bounds
    /// lowered to what the triangle allows; `pad` the ray test's rounding, `least_length`
    /// each grown cell's least |(u, v, 1)|.
    static void add_triangle(Cell* cells, int face, const glm::dvec3 (&p)[3], double d, uint32_t o,
                             double pad, const std::vector<double>& least_length);
    static int cell_index(float u) {
        // u in [-1, 1] on the face (a hair outside by rounding): its cell, clamped.
        const int k = static_cast<int>((u + 1.0f) * (0.5f * kResolution));
        return k < 0 ? 0 : (k >= kResolution ? kResolution - 1 : k);
    }

    vec3 end_{0.0f};
    float near2_ = kInfinity;  // squared; an empty cube calls nothing clear
    float slack_ = 0.0f;       // the most a shadow ray's origin lies off its sample
    std::vector<Cell> cells_;  // face (+x, -x, +y, -y, +z, -z), then row j, then column i
    // The list's objects, as leaves_convex reads them.
    std::vector<PrimitiveRange> objects_;
    std::vector<char> convex_;
    std::vector<vec3> centroid_;
};

/// Occluder cubes by key (the triangle list's key and the end's coordinates), kept by a
/// command whose renders share them: a drag in `svetlo serve` moves the camera, not the
/// lights.
class OccluderCubeCache : public SharedCache<OccluderCube> {
public:
    /// The most casters of one frame that get cubes (the rasterizer builds none beyond them:
    /// the still frame of a light with area has 16 and more, each a pass over the triangles
    /// and 1.1 MiB), and so the cubes a cache keeps: a frame's all.
    static constexpr size_t kMostPerFrame = 8;

    OccluderCubeCache() : SharedCache(kMostPerFrame) {}
};

}  // namespace svetlo
