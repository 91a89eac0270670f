#include "svetlo/geometry/accel.h"

#include <functional>

#include "svetlo/geometry/bvh.h"
#include "svetlo/geometry/embree_accel.h"
#include "svetlo/geometry/grid.h"
#include "svetlo/geometry/instanced_accel.h"
#include "svetlo/geometry/octree.h"
#include "svetlo/geometry/wide_bvh.h"

namespace svetlo {

namespace {

/// Every structure: its name (render.accel), what it is as this build and processor make it,
/// and how it is built. The one list accel_names, accel_description and make_accel read.
struct AccelEntry {
    std::string_view name;
    std::function<std::string()> description;
    std::function<std::unique_ptr<Accel>(const Geometry&, int threads)> make;
    /// Whether `make` builds the placements itself (Embree's own instances); otherwise each
    /// prototype gets a structure of its own under an InstancedAccel.
    bool places_instances = false;
};

const std::vector<AccelEntry>& accel_table() {
    static const std::string lanes = SVETLO_SIMD ? "SSE" : "scalar";
    static const std::vector<AccelEntry> table = {
        {"none", [] { return std::string("every primitive, no structure"); },
         [](const Geometry& g, int) { return std::make_unique<BruteForce>(g); }},
        {"grid", [] { return std::string("uniform grid, 3D-DDA"); },
         [](const Geometry& g, int) { return std::make_unique<Grid>(g); }},
        {"octree", [] { return std::string("octree"); },
         [](const Geometry& g, int) { return std::make_unique<Octree>(g); }},
        {"bvh2",
         [] { return std::string("binary binned-SAH BVH, one box at a time (the readable one)"); },
         [](const Geometry& g, int threads) { return std::make_unique<Bvh>(g, threads); }},
        {"bvh4", [] { return "four-wide BVH, " + lanes; },
         [](const Geometry& g, int threads) { return std::make_unique<WideBvh>(g, threads, 4); }},
        {"bvh",
         [] {
             return WideBvh::eight_wide_available()
                        ? std::string("eight-wide BVH, AVX2 (the fastest)")
                        : "four-wide BVH, " + lanes + " (the fastest here)";
         },
         [](const Geometry& g, int threads) { return std::make_unique<WideBvh>(g, threads); }},
        {"bvh16",
         [] {
             return WideBvh::sixteen_wide_available() ? std::string("sixteen-wide BVH, AVX-512")
                                                      : "no AVX-512 here: as bvh";
         },
         [](const Geometry& g, int threads) { return std::make_unique<WideBvh>(g, threads, 16); }},
        {"embree", [] { return std::string("Embree"); },
         [](const Geometry& g, int threads) { return make_embree_accel(g, threads); }, true},
    };
    return table;
}

const AccelEntry* find_accel(std::string_view name) {
    if (name == "embree" && !embree_available()) return nullptr;
    for (const AccelEntry& e : accel_table())
        if (e.name == name) return &e;
    return nullptr;
}

}  // namespace

std::vector<std::string> accel_names() {
    std::vector<std::string> names;
    for (const AccelEntry& e : accel_table())
        if (find_accel(e.name)) names.emplace_back(e.name);
    return names;
}

std::string accel_description(std::string_view name) {
    const AccelEntry* e = find_accel(name);
    return e ? e->description() : std::string();
}

std::unique_ptr<Accel> make_accel(std::string_view name, const Geometry& geometry, int threads) {
    const AccelEntry* e = find_accel(name);
    if (!e) return nullptr;
    if (e->places_instances) return e->make(geometry, threads);
    return make_instanced_accel(geometry, [&](const Geometry& g) { return e->make(g, threads); });
}

bool BruteForce::intersect(const Ray& ray, Hit& hit) const {
    RayPrecomputed pre(ray);
    hit = Hit{};
    hit.t = ray.tmax;
    return geometry_.intersect(prims_.data(), prims_.size(), ray, pre, hit);
}

bool BruteForce::occluded(const Ray& ray) const {
    return geometry_.occludes(prims_.data(), prims_.size(), ray, RayPrecomputed(ray));
}

}  // namespace svetlo
