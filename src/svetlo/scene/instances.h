// Instances for the engines that draw them as copies (docs/real-scenes.md, "Instances"): the
// rasterizer and radiosity tessellate every instance's objects into their world-space lists.
// The ray tracers do not copy: they trace the prototypes in their own space
// (geometry/instanced_accel.h).
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/scene/scene.h"

namespace svetlo {

/// The triangles of a mesh, or 1 for any other shape: what bounds the copies.
uint64_t object_triangles(const Object& object);

/// The sum of count(object) over every instance's objects: each prototype summed once, times
/// its placements.
template <class Count>
uint64_t sum_over_instances(const Scene& scene, Count&& count) {
    std::vector<uint64_t> per_prototype;
    for (const Prototype& p : scene.prototypes) {
        uint64_t n = 0;
        for (const Object& o : p.objects) n += count(o);
        per_prototype.push_back(n);
    }
    uint64_t total = 0;
    for (const Instance& i : scene.instances) total += per_prototype[i.prototype];
    return total;
}

/// The triangles the scene's instances stand for (each instance's prototype's meshes; a shape
/// counts one).
uint64_t instanced_triangles(const Scene& scene);

/// `object` of a prototype as `instance` places it: carried into the world, named after the
/// instance, its material replaced where the instance says so.
Object placed_object(const Object& object, const Instance& instance);

/// Every instance's objects written out in world space, their materials replaced where the
/// instance says so. Refused (Error naming `objects`) past kMaxCopiedTriangles triangles,
/// before anything is copied.
std::vector<Object> instance_copies(const Scene& scene);

/// The bound on instance_copies: 64 Mi triangles (about 3 GiB as copies).
inline constexpr uint64_t kMaxCopiedTriangles = uint64_t{64} << 20;

}  // namespace svetlo
