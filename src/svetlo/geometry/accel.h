// Acceleration structures: each answers closest-hit and any-hit queries over the bounded
// primitives of a Geometry, and must return the same hits as brute force.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "svetlo/geometry/geometry.h"

namespace svetlo {

class Accel {
public:
    virtual ~Accel() = default;
    /// Closest hit with 0 < t < ray.tmax; fills `hit` and returns true when there is one.
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    /// True when anything lies on the ray at 0 < t < ray.tmax.
    virtual bool occluded(const Ray& ray) const = 0;
    /// Bytes of the structure itself (not the geometry).
    virtual size_t memory_bytes() const = 0;
};

/// The names make_accel accepts, in the order `svetlo bench` lists them.
std::vector<std::string> accel_names();

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
    size_t memory_bytes() const override { return prims_.size() * sizeof(uint32_t); }

private:
    const Geometry& geometry_;
    std::vector<uint32_t> prims_;
};

}  // namespace svetlo
