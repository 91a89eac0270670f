// render.shadows "raytraced" in the rasterizer: the camera's visibility is rasterized, and each
// visible sample casts a shadow ray to each caster through a BVH of the same triangles the
// rasterizer drew (so that a sample never hits the surface it lies on), as hybrid real-time
// renderers do. Lights with area cast from the rasterizer's own VPLs, so that V is the
// fraction of the very points the shading sums that reach the sample. The BVH is the
// command's (f.accels) when an earlier frame of the same triangle list built it.
#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/ray.h"
#include "svetlo/raster/shadow_techniques.h"

namespace svetlo::raster {

namespace {

/// The shadow rays of up to 64 samples toward one point caster, lane by lane: shadow_ray()'s
/// numbers, bit for bit, in plain C++ the compiler vectorizes (glm's normalize is v times
/// 1 / sqrt(dot(v, v)), its dot (x x + y y) + z z; offset_ray_origin as in ray.h).
struct PointRays {
    static constexpr size_t kPacket = 64;
    alignas(32) float p[3][kPacket], n[3][kPacket];  // in: the samples' points and normals
    alignas(32) float o[3][kPacket], d[3][kPacket];  // out: the rays (tmax 1)
    alignas(32) bool ok[kPacket];                    // out: finite (else the sample is lit)

    void make(vec3 light_point, vec3 target_point, size_t count) {
        constexpr float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f;
        constexpr float kIntScale = 256.0f;
        // (Plain floats: glm's operator[] is a switch, which keeps the loop from vectorizing.)
        const float light[3] = {light_point.x, light_point.y, light_point.z};
        const float target[3] = {target_point.x, target_point.y, target_point.z};
        for (size_t r = 0; r < count; ++r) {
            float w[3], m[3];
            for (int c = 0; c < 3; ++c) w[c] = light[c] - p[c][r];
            const float inv = 1.0f / std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            for (int c = 0; c < 3; ++c) w[c] *= inv;
            // offset_ray_origin(p, n, w): off the surface along the normal on w's side.
            const bool flip = n[0][r] * w[0] + n[1][r] * w[1] + n[2][r] * w[2] < 0.0f;
            for (int c = 0; c < 3; ++c) m[c] = flip ? -n[c][r] : n[c][r];
            float off[3];
            for (int c = 0; c < 3; ++c) {
                const float q = p[c][r];
                const auto of = static_cast<int32_t>(kIntScale * m[c]);
                const float moved =
                    std::bit_cast<float>(std::bit_cast<int32_t>(q) + (q < 0.0f ? -of : of));
                const float nudged = q + kFloatScale * m[c];  // (both made: a select, no branch)
                off[c] = std::abs(q) < kOrigin ? nudged : moved;
            }
            // A little toward the light (shadow_ray()).
            const float toward = std::max(std::max(std::abs(p[0][r]), std::abs(p[1][r])),
                                          std::max(std::abs(p[2][r]), 1.0f)) /
                                 65536.0f;
            for (int c = 0; c < 3; ++c) {
                o[c][r] = off[c] + toward * w[c];
                d[c][r] = target[c] - o[c][r];
            }
            // Finite (x - x is 0 for a finite x, NaN for an infinite or NaN one).
            const float sum = o[0][r] + o[1][r] + o[2][r] + d[0][r] + d[1][r] + d[2][r];
            ok[r] = sum - sum == 0.0f;
        }
    }
};

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
        PointRays lanes;
        Ray rays[PointRays::kPacket];
        uint32_t slot[PointRays::kPacket];    // each sample's place in `out`
        uint32_t traced[PointRays::kPacket];  // each ray's sample in the packet
        bool blocked[PointRays::kPacket];
        size_t n = 0;
        auto flush = [&] {
            lanes.make(casters_[k].position, targets_[k], n);
            size_t count_rays = 0;
            for (size_t r = 0; r < n; ++r) {
                if (!lanes.ok[r]) {  // not finite: lit
                    out[slot[r]] = 1.0f;
                    continue;
                }
                Ray& ray = rays[count_rays];
                ray.o = vec3(lanes.o[0][r], lanes.o[1][r], lanes.o[2][r]);
                ray.d = vec3(lanes.d[0][r], lanes.d[1][r], lanes.d[2][r]);
                ray.tmax = 1.0f;
                traced[count_rays++] = static_cast<uint32_t>(r);
            }
            accel_->occluded_toward(targets_[k], rays, count_rays, blocked);
            for (size_t r = 0; r < count_rays; ++r) out[slot[traced[r]]] = blocked[r] ? 0.0f : 1.0f;
            n = 0;
        };
        auto add = [&](size_t m) {
            const ShadowSample& sample = samples[at[m]];
            for (int c = 0; c < 3; ++c) {
                lanes.p[c][n] = sample.p[c];
                lanes.n[c][n] = sample.n[c];
            }
            slot[n++] = static_cast<uint32_t>(m);
            if (n == PointRays::kPacket) flush();
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
