// Acceleration structures: each answers closest-hit and any-hit queries over the bounded
// primitives of a Geometry, and must return the same hits as brute force.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "svetlo/geometry/geometry.h"

namespace svetlo {

/// The work of one closest-hit query (the bvh_cost AOV): inner nodes whose children's boxes
/// were tested, and primitives tested (a packet counts its four lanes).
struct TraversalCost {
    uint32_t nodes = 0, primitives = 0;
};

/// What an any-hit query asks of each triangle it meets before it counts it (the alpha's
/// holes, shading/cutouts.h): a function and its context, so that no query allocates.
struct HitFilter {
    bool (*counts)(const void* context, const Ray& ray, const Hit& hit) = nullptr;
    const void* context = nullptr;
    bool operator()(const Ray& ray, const Hit& hit) const { return counts(context, ray, hit); }
};

class Accel {
public:
    virtual ~Accel() = default;
    /// Closest hit with 0 < t < ray.tmax; fills `hit` and returns true when there is one.
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    /// The same, adding its work to `cost`. False from a structure that does not count (then
    /// nothing is traced): see counts_cost().
    virtual bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
        (void)cost;
        return intersect(ray, hit);
    }
    virtual bool counts_cost() const { return false; }
    /// True when anything lies on the ray at 0 < t < ray.tmax.
    virtual bool occluded(const Ray& ray) const = 0;
    /// Whether the structure answers occluded_if (WideBvh's bvh4 and bvh).
    virtual bool filters_hits() const { return false; }
    /// True when the ray meets, at 0 < t < ray.tmax, a triangle whose hit (t, prim, u, v, in
    /// the structure's space) `counts` says counts, or any other primitive (an analytic shape
    /// is not asked: its first hit may hide a second). Called only where filters_hits().
    virtual bool occluded_if(const Ray& ray, HitFilter counts) const {
        (void)counts;
        return occluded(ray);
    }
    /// occluded(rays[k]) into blocked[k] for `count` rays that end at one point: each ray's
    /// segment, o + t d for t in [0, tmax], ends at `end` (to a few ulps), as shadow rays toward
    /// a point light do. A structure may test them together (WideBvh does); the answers are
    /// occluded()'s, bit for bit. `skip`, when given, holds per ray primitives [first, end) that
    /// the caller knows it cannot meet (the convex object it leaves, the rasterizer's shadow
    /// rays): a structure may leave them untested (WideBvh leaves a leaf of them untested).
    virtual void occluded_toward(vec3 end, const Ray* rays, size_t count, bool* blocked,
                                 const PrimitiveRange* skip = nullptr) const {
        (void)end;
        (void)skip;
        for (size_t k = 0; k < count; ++k) blocked[k] = occluded(rays[k]);
    }
    /// Bytes of the structure itself (not the geometry).
    virtual size_t memory_bytes() const = 0;
};

/// The names make_accel accepts, in the order `svetlo bench` lists them.
std::vector<std::string> accel_names();

/// What the structure called `name` is, in a few words, as this build and processor make it:
/// "bvh2" is the binary BVH a student reads first; "bvh" the fastest (docs/geometry.md).
std::string accel_description(std::string_view name);

/// Builds the structure called `name` (one of accel_names()) over `geometry`'s bounded primitives
/// on `threads` threads (0 = all cores). Returns nullptr for an unknown name.
std::unique_ptr<Accel> make_accel(std::string_view name, const Geometry& geometry, int threads = 0);

/// Every primitive for every ray: the reference the others are tested against.
class BruteForce final : public Accel {
public:
    explicit BruteForce(const Geometry& geometry)
        : geometry_(geometry), prims_(geometry.bounded_primitives()) {}
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override {
        cost.primitives += static_cast<uint32_t>(prims_.size());
        return intersect(ray, hit);
    }
    bool counts_cost() const override { return true; }
    size_t memory_bytes() const override { return prims_.size() * sizeof(uint32_t); }

private:
    const Geometry& geometry_;
    std::vector<uint32_t> prims_;
};

}  // namespace svetlo
