#include "svetlo/rt/rt_scene.h"

#include "svetlo/core/error.h"
#include "svetlo/geometry/scene_geometry.h"

namespace svetlo {

RtScene::RtScene(const Scene& scene, const std::string& accel, int threads)
    : scene_(scene), lights_(scene) {
    geometry_ = build_geometry(object_pointers(scene.objects, lights_.area_light_quads()));
    unbounded_ = geometry_.unbounded_primitives();
    accel_ = make_accel(accel, geometry_, threads);
    if (!accel_) {
        throw Error(scene.path.string(), "render.accel",
                    accel == "embree" ? std::string("this svetlo was built without Embree")
                                      : "unknown accelerator '" + accel + "'");
    }
}

namespace {

/// A ray whose origin or direction is not finite meets nothing (and never reaches the
/// accelerators, whose traversal assumes numbers).
bool traceable(const Ray& ray) {
    return std::isfinite(ray.o.x + ray.o.y + ray.o.z + ray.d.x + ray.d.y + ray.d.z);
}

}  // namespace

bool RtScene::intersect(const Ray& ray, Hit& hit) const {
    if (!traceable(ray)) return false;
    bool found = accel_->intersect(ray, hit);
    if (unbounded_.empty()) return found;
    if (!found) hit.t = ray.tmax;
    RayPrecomputed pre(ray);
    return geometry_.intersect(unbounded_.data(), unbounded_.size(), ray, pre, hit) || found;
}

bool RtScene::occluded(const Ray& ray) const {
    if (!traceable(ray)) return false;
    if (!unbounded_.empty() &&
        geometry_.occludes(unbounded_.data(), unbounded_.size(), ray, RayPrecomputed(ray))) {
        return true;
    }
    return accel_->occluded(ray);
}

}  // namespace svetlo
