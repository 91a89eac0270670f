// render.shadows "raytraced" in the rasterizer: the camera's visibility is rasterized, and each
// visible sample casts a shadow ray to each caster through a BVH of the same triangles the
// rasterizer drew (so that a sample never hits the surface it lies on), as hybrid real-time
// renderers do. Lights with area cast from the rasterizer's own VPLs, so that V is the
// fraction of the very points the shading sums that reach the sample. The BVH is the
// command's (f.accels) when an earlier frame of the same triangle list built it.
#include <algorithm>
#include <climits>
#include <cmath>

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
        Ray ray;
        if (!shadow_ray(k, at, ray)) return 1.0f;
        return accel_->occluded(ray) ? 0.0f : 1.0f;
    }

    // Toward a point (every caster but a directional light), the rays of nearby samples end
    // at one point and the BVH tests them together (Accel::occluded_toward), 8 x 8 pixels at
    // a time; the answers are lit()'s. No virtual call a ray.
    void lit_many(size_t k, const ShadowSample* samples, const uint32_t* at, size_t count,
                  float* out) const override {
        if (casters_[k].kind == ShadowCaster::Kind::Directional) {
            for (size_t m = 0; m < count; ++m) out[m] = lit(k, samples[at[m]]);
            return;
        }
        constexpr size_t kPacket = 64;
        Ray rays[kPacket];
        uint32_t slot[kPacket];  // each ray's place in `out`
        bool blocked[kPacket];
        size_t n = 0;
        auto flush = [&] {
            accel_->occluded_toward(targets_[k], rays, n, blocked);
            for (size_t r = 0; r < n; ++r) out[slot[r]] = blocked[r] ? 0.0f : 1.0f;
            n = 0;
        };
        auto add = [&](size_t m) {
            if (!shadow_ray(k, samples[at[m]], rays[n])) {
                out[m] = 1.0f;
                return;
            }
            slot[n++] = static_cast<uint32_t>(m);
            if (n == kPacket) flush();
        };
        // The samples come row after row (shadow_masks.cpp): each band of 8 rows is cut into
        // blocks of 8 columns, taken from the band's rows with a cursor each. (In another
        // order every sample is still taken once, at the latest by the last sweep.)
        constexpr int kBlock = 8;
        for (size_t first = 0; first < count;) {
            const int band = samples[at[first]].j / kBlock;
            size_t cursor[kBlock], stop[kBlock];
            int rows = 0, lo = INT_MAX, hi = INT_MIN;
            size_t last = first;
            while (last < count && rows < kBlock && samples[at[last]].j / kBlock == band) {
                const int row = samples[at[last]].j;
                cursor[rows] = last;
                while (last < count && samples[at[last]].j == row) ++last;
                stop[rows++] = last;
                lo = std::min(lo, samples[at[cursor[rows - 1]]].i / kBlock);
                hi = std::max(hi, samples[at[last - 1]].i / kBlock);
            }
            hi = std::min(hi, lo + 64);
            for (int block = lo; block <= hi; ++block) {
                for (int r = 0; r < rows; ++r) {
                    for (; cursor[r] < stop[r] && samples[at[cursor[r]]].i / kBlock <= block;
                         ++cursor[r])
                        add(cursor[r]);
                }
                if (n > 0) flush();
            }
            for (int r = 0; r < rows; ++r)
                for (; cursor[r] < stop[r]; ++cursor[r]) add(cursor[r]);
            first = last;
        }
        if (n > 0) flush();
    }

private:
    /// The shadow ray from sample `at` to caster k: off the surface along its normal, and a
    /// little toward the light (a rasterized point is interpolated, and near a concave edge it
    /// can lie a rounding error behind the other face, which a ray leaving along the normal
    /// alone would then meet); to the caster's target, t in (0, 1), or toward a directional
    /// light without end. False when it is not finite (then the sample counts as lit).
    bool shadow_ray(size_t k, const ShadowSample& at, Ray& ray) const {
        const ShadowCaster& c = casters_[k];
        const vec3 wi = c.to_light(at.p);
        const vec3 a = glm::abs(at.p);
        const float toward = std::max(std::max(a.x, a.y), std::max(a.z, 1.0f)) / 65536.0f;
        ray = Ray{offset_ray_origin(at.p, at.n, wi) + toward * wi, wi, kInfinity};
        if (c.kind != ShadowCaster::Kind::Directional) {
            ray.d = targets_[k] - ray.o;  // to the caster
            ray.tmax = 1.0f;
        }
        return std::isfinite(ray.o.x + ray.o.y + ray.o.z + ray.d.x + ray.d.y + ray.d.z);
    }

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
