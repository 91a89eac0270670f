#include "svetlo/rt/accel.h"

#include "svetlo/rt/bvh.h"

namespace svetlo {

std::vector<std::string> accel_names() { return {"none", "bvh"}; }

std::unique_ptr<Accel> make_accel(std::string_view name, const Geometry& geometry, int threads) {
    if (name == "none") return std::make_unique<BruteForce>(geometry);
    if (name == "bvh") return std::make_unique<Bvh>(geometry, threads);
    return nullptr;
}

bool BruteForce::intersect(const Ray& ray, Hit& hit) const {
    RayPrecomputed pre(ray);
    hit = Hit{};
    hit.t = ray.tmax;
    bool found = false;
    for (uint32_t id : prims_) found |= geometry_.intersect(id, ray, pre, hit);
    return found;
}

bool BruteForce::occluded(const Ray& ray) const {
    RayPrecomputed pre(ray);
    for (uint32_t id : prims_) {
        Hit hit;
        hit.t = ray.tmax;
        if (geometry_.intersect(id, ray, pre, hit)) return true;
    }
    return false;
}

}  // namespace svetlo
