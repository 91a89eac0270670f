// The ray tracer's view of a Scene: world-space geometry (the objects, then the area lights'
// quads), the light set, and an acceleration structure. Engines that trace rays (whitted,
// path) share it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/scene/scene.h"
#include "svetlo/shading/light_set.h"

namespace svetlo {

class RtScene {
public:
    /// Builds with the accelerator `accel` (see accel_names()) on `threads` threads. Throws Error
    /// for what the light set cannot sample (light_set.h).
    RtScene(const Scene& scene, const std::string& accel, int threads);

    const Scene& scene() const { return scene_; }
    const Geometry& geometry() const { return geometry_; }
    const LightSet& lights() const { return lights_; }
    /// The scene's materials, then the area lights' (LightSet::materials).
    const std::vector<Material>& materials() const { return lights_.materials(); }
    const Accel& accel() const { return *accel_; }

    bool intersect(const Ray& ray, Hit& hit) const;
    bool occluded(const Ray& ray) const;

private:
    const Scene& scene_;
    LightSet lights_;
    Geometry geometry_;
    std::vector<uint32_t> unbounded_;
    std::unique_ptr<Accel> accel_;
};

}  // namespace svetlo
