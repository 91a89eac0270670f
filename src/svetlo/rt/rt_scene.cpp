#include "svetlo/rt/rt_scene.h"

#include <algorithm>

#include "svetlo/core/error.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/scene/material_sources.h"

namespace svetlo {

RtScene::RtScene(const Scene& scene, const std::string& accel, int threads, AccelCache* cache)
    : scene_(scene), lights_(scene), environment_(scene) {
    // A scene made in code, not read, has no key: it builds its own.
    const std::string key = scene.geometry_key.empty() ? "" : scene.geometry_key + " " + accel;
    built_ = shared_entry<BuiltGeometry>(cache, key, [&](BuiltGeometry& b) {
        b.geometry =
            build_geometry(object_pointers(scene.objects, lights_.area_light_quads()), &b.ranges);
        place_instances(scene, b.geometry);
        b.accel = make_accel(accel, b.geometry, threads);
        if (!b.accel) {
            throw Error(scene.path.string(), "render.accel",
                        accel == "embree" ? std::string("this svetlo was built without Embree")
                                          : "unknown accelerator '" + accel + "'");
        }
    });
    const auto& sources = lights_.sources();
    for (size_t k = 0; k < sources.size(); ++k) {
        if (sources[k].object < 0) continue;
        const PrimitiveRange& r = built_->ranges[static_cast<size_t>(sources[k].object)];
        emitter_ranges_.push_back({r.first, r.end, static_cast<int>(k)});
    }
    std::sort(emitter_ranges_.begin(), emitter_ranges_.end(),
              [](const EmitterRange& a, const EmitterRange& b) { return a.first < b.first; });
    for (const Material& m : materials()) {
        textured_.push_back(any_source(m, is_textured) ? 1 : 0);
        uniform_bsdfs_.push_back(make_bsdf(m, vec2(0.0f), scene.textures));
    }
    unbounded_ = geometry().unbounded_primitives();
    cutouts_ = std::make_unique<Cutouts>(geometry(), materials(), scene.textures);
}

int RtScene::light_source_of(const Hit& hit) const {
    if (hit.instance != Hit::kNone) return -1;  // an instance never emits (scene.h)
    const uint32_t prim = hit.prim;
    auto it = std::upper_bound(emitter_ranges_.begin(), emitter_ranges_.end(), prim,
                               [](uint32_t id, const EmitterRange& r) { return id < r.first; });
    if (it == emitter_ranges_.begin()) return -1;
    --it;
    return prim < it->end ? it->source : -1;
}

uint32_t RtScene::light_prim_of(const Hit& hit) const {
    if (hit.instance != Hit::kNone) return ~0u;
    const uint32_t prim = hit.prim;
    auto it = std::upper_bound(emitter_ranges_.begin(), emitter_ranges_.end(), prim,
                               [](uint32_t id, const EmitterRange& r) { return id < r.first; });
    if (it == emitter_ranges_.begin()) return ~0u;
    --it;
    if (prim >= it->end) return ~0u;
    // An object's primitives lie in the same order in both geometries.
    return prim - it->first + lights_.sources()[static_cast<size_t>(it->source)].range_first;
}

namespace {

/// A ray whose origin or direction is not finite meets nothing (and never reaches the
/// accelerators, whose traversal assumes numbers).
bool traceable(const Ray& ray) {
    return std::isfinite(ray.o.x + ray.o.y + ray.o.z + ray.d.x + ray.d.y + ray.d.z);
}

}  // namespace

bool RtScene::intersect(const Ray& ray, Hit& hit) const {
    return cutouts_->closest_solid(ray, hit,
                                   [&](const Ray& r, Hit& h) { return closest(r, h, nullptr); });
}

bool RtScene::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
    return closest(ray, hit, &cost);
}

bool RtScene::closest(const Ray& ray, Hit& hit, TraversalCost* cost) const {
    if (!traceable(ray)) return false;
    bool found =
        cost ? built_->accel->intersect_cost(ray, hit, *cost) : built_->accel->intersect(ray, hit);
    if (unbounded_.empty()) return found;
    if (!found) hit.t = ray.tmax;
    if (cost) cost->primitives += static_cast<uint32_t>(unbounded_.size());
    RayPrecomputed pre(ray);
    return geometry().intersect(unbounded_.data(), unbounded_.size(), ray, pre, hit) || found;
}

void RtScene::check_counts_cost() const {
    if (!built_->accel->counts_cost()) {
        throw Error(scene_.path.string(), "render.accel",
                    "the bvh_cost AOV needs render.accel bvh or none (" + scene_.render.accel +
                        " does not count its work)");
    }
}

Color RtScene::camera_ray_cost(const Ray& ray) const {
    TraversalCost cost;
    Hit hit;
    intersect_cost(ray, hit, cost);
    const auto nodes = static_cast<float>(cost.nodes), prims = static_cast<float>(cost.primitives);
    return Color(nodes, prims, nodes + prims);
}

bool RtScene::occluded(const Ray& ray) const {
    if (!traceable(ray)) return false;
    if (cutouts_->any() && !cutouts_->holes_on_triangles_only()) {
        Hit hit;  // a shape can be a hole: closest hits in turn (Cutouts::closest_solid)
        return intersect(ray, hit);
    }
    // The unbounded shapes are no holes here.
    if (!unbounded_.empty() &&
        geometry().occludes(unbounded_.data(), unbounded_.size(), ray, RayPrecomputed(ray))) {
        return true;
    }
    return cutouts_->occluded_solid(ray, *built_->accel);
}

}  // namespace svetlo
