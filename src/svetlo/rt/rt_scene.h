// The ray tracer's view of a Scene: world-space geometry, the materials (the scene's plus
// one per area light), the emitters, and an acceleration structure. Engines that trace rays
// (whitted, path, bench) share it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/emitters.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

class RtScene {
public:
    /// Builds with the accelerator `accel` (see accel_names()) on `threads` threads. Throws Error
    /// for what the ray tracer cannot handle (an emissive shape under a non-uniform scale).
    RtScene(const Scene& scene, const std::string& accel, int threads);

    const Scene& scene() const { return scene_; }
    const Geometry& geometry() const { return geometry_; }
    const std::vector<Material>& materials() const { return materials_; }
    const std::vector<Emitter>& emitters() const { return emitters_; }
    const Accel& accel() const { return *accel_; }
    /// Indices into scene().lights of the point, directional and spot lights.
    const std::vector<int>& punctual_lights() const { return punctual_; }

    bool intersect(const Ray& ray, Hit& hit) const;
    bool occluded(const Ray& ray) const;

private:
    const Scene& scene_;
    Geometry geometry_;
    std::vector<Material> materials_;
    std::vector<Emitter> emitters_;
    std::vector<int> punctual_;
    std::vector<uint32_t> unbounded_;
    std::unique_ptr<Accel> accel_;
};

/// Bakes the scene's objects and area lights into world-space geometry. `materials` receives
/// the scene's materials plus one emissive material per area light; `emitters` one entry per
/// area light and per emissive object.
Geometry build_geometry(const Scene& scene, std::vector<Material>& materials,
                        std::vector<Emitter>& emitters);

}  // namespace svetlo
