#include "svetlo/geometry/accel.h"

#include "svetlo/geometry/bvh.h"
#include "svetlo/geometry/embree_accel.h"
#include "svetlo/geometry/grid.h"
#include "svetlo/geometry/octree.h"
#include "svetlo/geometry/wide_bvh.h"

namespace svetlo {

std::vector<std::string> accel_names() {
    std::vector<std::string> names = {"none", "grid", "octree", "bvh2", "bvh4", "bvh"};
    if (embree_available()) names.push_back("embree");
    return names;
}

std::string accel_description(std::string_view name) {
    const std::string lanes = SVETLO_SIMD ? "SSE" : "scalar";
    if (name == "none") return "every primitive, no structure";
    if (name == "grid") return "uniform grid, 3D-DDA";
    if (name == "octree") return "octree";
    if (name == "bvh2") return "binary binned-SAH BVH, one box at a time (the readable one)";
    if (name == "bvh4") return "four-wide BVH, " + lanes;
    if (name == "bvh")
        return WideBvh::eight_wide_available() ? "eight-wide BVH, AVX2 (the fastest)"
                                               : "four-wide BVH, " + lanes + " (the fastest here)";
    if (name == "embree") return "Embree";
    return "";
}

std::unique_ptr<Accel> make_accel(std::string_view name, const Geometry& geometry, int threads) {
    if (name == "none") return std::make_unique<BruteForce>(geometry);
    if (name == "grid") return std::make_unique<Grid>(geometry);
    if (name == "octree") return std::make_unique<Octree>(geometry);
    if (name == "bvh2") return std::make_unique<Bvh>(geometry, threads);
    if (name == "bvh4") return std::make_unique<WideBvh>(geometry, threads, 4);
    if (name == "bvh") return std::make_unique<WideBvh>(geometry, threads);
    if (name == "embree" && embree_available()) return make_embree_accel(geometry, threads);
    return nullptr;
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
