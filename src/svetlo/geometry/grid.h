// A uniform grid traversed by 3D-DDA (Amanatides and Woo, "A Fast Voxel Traversal Algorithm
// for Ray Tracing", Eurographics 1987). The scene's bounds are cut into about
// kCellsPerPrimitive cells per primitive, as cubic as the bounds allow; each cell lists the
// primitives whose bounds overlap it (compressed rows). The ray walks the cells it pierces
// front to back and stops in the first cell that holds a hit no farther than the cell's far
// side. Fast to build and good when primitives are small and evenly spread; poor when a
// small region holds most of them ("teapot in a stadium").
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "svetlo/geometry/accel.h"

namespace svetlo {

class Grid final : public Accel {
public:
    explicit Grid(const Geometry& geometry);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override {
        return cell_start_.size() * sizeof(uint32_t) + cell_prims_.size() * sizeof(uint32_t);
    }

private:
    /// Walks the cells along the ray; `visit(first, last, t_exit)` gets the primitive range of
    /// each non-empty cell and the ray's exit distance from it, and returns true to stop.
    template <class Visit>
    void walk(const Ray& ray, float tmax, Visit&& visit) const;

    const Geometry& geometry_;
    Bounds3 bounds_;
    std::array<int, 3> res_{0, 0, 0};
    vec3 cell_size_{0.0f};
    std::vector<uint32_t> cell_start_;  // res.x * res.y * res.z + 1 offsets into cell_prims_
    std::vector<uint32_t> cell_prims_;
};

}  // namespace svetlo
