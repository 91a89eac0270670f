// render.shadows "raytraced" in the rasterizer: the camera's visibility is rasterized, and each
// visible sample casts a shadow ray to each caster through a BVH of the same triangles the
// rasterizer drew (so that a sample never hits the surface it lies on), as hybrid real-time
// renderers do. Lights with area cast from the rasterizer's own VPLs, so that V is the
// fraction of the very points the shading sums that reach the sample. The BVH is the
// command's (f.accels) when an earlier frame of the same triangle list built it.
#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/ray.h"
#include "svetlo/raster/shadow_techniques.h"

namespace svetlo::raster {

namespace {

class RaytracedShadows final : public ShadowTechniqueState {
public:
    RaytracedShadows(const Scene& scene, const TriangleList& list, const FrameShading& f,
                     int threads) {
        casters_ = shadow_casters(scene, f.lights->set, f.lights->vpls);
        // Each caster's end of its rays: a point on an emitter moved off its own surface to
        // the front, the side of every sample it lights (lit() is called only for those).
        for (const ShadowCaster& c : casters_) {
            targets_.push_back(glm::length(c.normal) > 0.0f
                                   ? offset_ray_origin(c.position, c.normal, c.normal)
                                   : c.position);
        }
        const std::string key = f.list_key.empty() ? "" : f.list_key + " shadow bvh";
        built_ = shared_entry<BuiltGeometry>(f.accels, key, [&](BuiltGeometry& b) {
            b.geometry = triangle_geometry(list);
            b.accel = make_accel("bvh", b.geometry, threads);
        });
        accel_ = built_->accel.get();
    }

    float lit(size_t k, const ShadowSample& at) const override {
        const ShadowCaster& c = casters_[k];
        const vec3 wi = c.to_light(at.p);
        // Off the surface along its normal, and a little toward the light: a rasterized
        // point is interpolated, and near a concave edge it can lie a rounding error behind
        // the other face, which a ray leaving along the normal alone would then meet.
        const vec3 a = glm::abs(at.p);
        const float toward = std::max(std::max(a.x, a.y), std::max(a.z, 1.0f)) / 65536.0f;
        Ray ray{offset_ray_origin(at.p, at.n, wi) + toward * wi, wi, kInfinity};
        if (c.kind != ShadowCaster::Kind::Directional) {
            ray.d = targets_[k] - ray.o;  // to the caster
            ray.tmax = 1.0f;
        }
        if (!std::isfinite(ray.o.x + ray.o.y + ray.o.z + ray.d.x + ray.d.y + ray.d.z)) return 1.0f;
        return accel_->occluded(ray) ? 0.0f : 1.0f;
    }

    // lit() for each sample, called directly (this class is final): no virtual call a ray.
    void lit_many(size_t k, const ShadowSample* samples, const uint32_t* at, size_t count,
                  float* out) const override {
        for (size_t m = 0; m < count; ++m) out[m] = lit(k, samples[at[m]]);
    }

private:
    std::vector<vec3> targets_;                   // per caster: where its rays end
    std::shared_ptr<const BuiltGeometry> built_;  // the triangles and their BVH
    const Accel* accel_ = nullptr;
};

}  // namespace

std::unique_ptr<ShadowTechniqueState> make_raytraced_shadows(const Scene& scene,
                                                             const TriangleList& list,
                                                             const FrameShading& f, int threads,
                                                             PassMemory*) {
    return std::make_unique<RaytracedShadows>(scene, list, f, threads);
}

}  // namespace svetlo::raster
