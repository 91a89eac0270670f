// The ray tracer's view of a Scene: world-space geometry (the objects, then the area lights'
// quads), the light set, and an acceleration structure. Engines that trace rays (whitted,
// path) share it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/scene/scene.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/cutouts.h"
#include "svetlo/shading/environment.h"
#include "svetlo/shading/light_set.h"
#include "svetlo/shading/normal_map.h"

namespace svetlo {

class RtScene {
public:
    /// Builds with the accelerator `accel` (see accel_names()) on `threads` threads, or takes
    /// the geometry and structure from `cache` when it holds the scene's. Throws Error for
    /// what the light set cannot sample (light_set.h).
    RtScene(const Scene& scene, const std::string& accel, int threads, AccelCache* cache = nullptr);
    RtScene(const RtScene&) = delete;  // cutouts_ refers to its members
    RtScene& operator=(const RtScene&) = delete;

    const Scene& scene() const { return scene_; }
    const Geometry& geometry() const { return built_->geometry; }
    const LightSet& lights() const { return lights_; }
    /// What comes from far away: the environment map or the uniform background.
    const Environment& environment() const { return environment_; }
    /// The scene's materials, then the area lights' (LightSet::materials).
    const std::vector<Material>& materials() const { return lights_.materials(); }
    const Accel& accel() const { return *built_->accel; }
    /// The surface at a hit, its shading normal bent by its material's normal map.
    SurfaceHit surface(const Ray& ray, const Hit& hit) const {
        SurfaceHit s = geometry().surface(ray, hit);
        const Material& m = materials()[s.material];
        s.coat_ns = coat_shading_normal(m, s.varyings(), s.ns, s.ng, s.tangent, scene_.textures);
        if (m.normal_map.present())
            s.ns =
                mapped_normal(m.normal_map, s.varyings(), s.ns, s.ng, s.tangent, scene_.textures);
        return s;
    }
    /// The BSDF of material `material` at a point with varyings `at`: made once for a
    /// material without textures, at each call for one with.
    Bsdf bsdf(uint32_t material, const Varyings& at) const {
        return textured_[material] ? make_bsdf(materials()[material], at, scene_.textures)
                                   : uniform_bsdfs_[material];
    }

    /// The index in lights().sources() of the light with area that the primitive of `hit`
    /// belongs to, or -1 (the path tracer weighs an emitter it meets by the pdf of sampling it).
    int light_source_of(const Hit& hit) const;
    /// The same primitive in the light set's geometry (LightSet::pdf's `prim`); ~0u for none.
    uint32_t light_prim_of(const Hit& hit) const;

    /// The primitives of each object of the scene, then of each area light's quad.
    const std::vector<PrimitiveRange>& object_ranges() const { return built_->ranges; }

    /// The closest hit and whether anything blocks the ray, seeing through alpha's holes
    /// (cutouts.h).
    bool intersect(const Ray& ray, Hit& hit) const;
    bool occluded(const Ray& ray) const;
    /// intersect(), adding its work to `cost` (the unbounded primitives count as tested);
    /// needs an accel() that counts_cost().
    bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const;
    /// The bvh_cost AOV's value for a camera ray: nodes, primitives, and their sum.
    Color camera_ray_cost(const Ray& ray) const;
    /// Before a render with the bvh_cost AOV: throws Error naming render.accel when the
    /// structure does not count its work.
    void check_counts_cost() const;

private:
    /// The closest hit of the structure and the unbounded primitives, counting the work into
    /// `cost` when it is given.
    bool closest(const Ray& ray, Hit& hit, TraversalCost* cost) const;

    const Scene& scene_;
    LightSet lights_;
    Environment environment_;
    std::shared_ptr<const BuiltGeometry> built_;
    std::vector<Bsdf> uniform_bsdfs_;  // per material (meaningless where textured)
    std::vector<char> textured_;       // per material
    std::vector<uint32_t> unbounded_;
    std::unique_ptr<Cutouts> cutouts_;
    struct EmitterRange {
        uint32_t first, end;  // primitive ids [first, end)
        int source;           // index in lights_.sources()
    };
    std::vector<EmitterRange> emitter_ranges_;  // ascending by first
};

}  // namespace svetlo
