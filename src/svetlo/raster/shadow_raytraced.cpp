// render.shadows "raytraced" in the rasterizer: the camera's visibility is rasterized, and each
// visible sample casts a shadow ray to each caster through a BVH of the same triangles the
// rasterizer drew (so that a sample never hits the surface it lies on), as hybrid real-time
// renderers do. Lights with area cast from the rasterizer's own VPLs, so that V is the
// fraction of the very points the shading sums that reach the sample. The BVH is the
// command's (FrameCaches::accels) when an earlier frame of the same triangle list built it.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/geometry/ray.h"
#include "svetlo/raster/placed_draws.h"
#include "svetlo/raster/shadow_techniques.h"
#include "svetlo/shading/cutouts.h"

namespace svetlo::raster {

namespace {

/// The origin of a shadow ray from a sample at p (unit normal n, the side the camera sees)
/// along unit wi: off the surface along the normal, and a little toward the light (a
/// rasterized point is interpolated, and near a concave edge it can lie a rounding error
/// behind the other face, which a ray leaving along the normal alone would then meet).
inline vec3 shadow_origin(vec3 p, vec3 n, vec3 wi) {
    const vec3 a = glm::abs(p);
    const float toward = std::max(std::max(a.x, a.y), std::max(a.z, 1.0f)) / 65536.0f;
    return offset_ray_origin(p, n, wi) + toward * wi;
}

/// Whether a ray is finite (x - x is 0 for a finite x, NaN for an infinite or NaN one; no
/// branch, unlike isfinite).
inline bool finite_ray(vec3 o, vec3 d) {
    const float sum = o.x + o.y + o.z + d.x + d.y + d.z;
    return sum - sum == 0.0f;
}

/// The shadow rays of up to 64 samples toward one point caster at `light`, ending at
/// `target`, lane by lane (the same statement as lit()'s rays, which the compiler vectorizes
/// here).
struct PointRays {
    static constexpr size_t kPacket = 64;
    alignas(32) float p[3][kPacket], n[3][kPacket];  // in: the samples' points and normals
    alignas(32) float o[3][kPacket], d[3][kPacket];  // out: the rays (tmax 1)
    alignas(32) bool ok[kPacket];                    // out: finite (else the sample is lit)

    void make(vec3 light, vec3 target, size_t count) {
        for (size_t r = 0; r < count; ++r) {
            const vec3 at(p[0][r], p[1][r], p[2][r]);
            // (ShadowCaster::to_light of a point: with the caster itself in the loop, the
            // drag measured slower.)
            const vec3 origin =
                shadow_origin(at, vec3(n[0][r], n[1][r], n[2][r]), glm::normalize(light - at));
            const vec3 to = target - origin;
            o[0][r] = origin.x;
            o[1][r] = origin.y;
            o[2][r] = origin.z;
            d[0][r] = to.x;
            d[1][r] = to.y;
            d[2][r] = to.z;
            ok[r] = finite_ray(origin, to);
        }
    }
};

class RaytracedShadows final : public ShadowTechniqueState {
public:
    RaytracedShadows(const Scene& scene, const TriangleList& list, const FrameShading& f,
                     const FrameCaches& caches, int threads)
        : list_(list), placed_(f.placed != nullptr) {
        casters_ = shadow_casters(scene, f.lights->set, f.lights->vpls);
        // Each caster's end of its rays: a point on an emitter moved off its own surface to
        // the front, the side of every sample it lights (lit() is called only for those).
        for (const ShadowCaster& c : casters_) {
            targets_.push_back(glm::length(c.normal) > 0.0f
                                   ? offset_ray_origin(c.position, c.normal, c.normal)
                                   : c.position);
        }
        const std::string key = caches.list_key.empty() ? "" : caches.list_key + " shadow bvh";
        built_ = shared_entry<BuiltGeometry>(caches.accels, key, [&](BuiltGeometry& b) {
            b.geometry = triangle_geometry(list);
            if (f.placed) f.placed->add_to(b.geometry);  // instances placed, not copied
            b.accel = make_accel("bvh", b.geometry, threads);
        });
        accel_ = built_->accel.get();
        // Alpha's holes (cutouts.h): the rays see through them.
        cutouts_ = std::make_unique<Cutouts>(built_->geometry, f.materials, scene.textures);
        if (cutouts_->any()) {
            see_through_ = std::make_unique<CutoutAccel>(*accel_, *cutouts_);
            accel_ = see_through_.get();
        }
        // The point casters' occluder cubes, where there are few casters (a frame's point
        // lights, or a preview's lights with area from one point each). A cube costs a pass
        // over the triangles (docs/performance.md, "Costs the code's choices rest on") and
        // spares the rays of most lit samples: a command that keeps them (svetlo serve,
        // svetlo compare) builds each once for all its frames, another only for a frame of
        // many samples a triangle.
        cubes_.resize(casters_.size());
        const double samples = static_cast<double>(scene.film.width) * scene.film.height *
                               std::max(scene.render.spp, 1);
        const bool kept = caches.occluder_cubes && !caches.list_key.empty();
        // (A cube is made of a list's triangles: not of instances drawn in place.)
        if (placed_ || casters_.size() > OccluderCubeCache::kMostPerFrame ||
            (!kept && samples < kSamplesPerTriangle * static_cast<double>(list.triangle_count())))
            return;
        for (size_t k = 0; k < casters_.size(); ++k) {
            if (casters_[k].kind == ShadowCaster::Kind::Directional) continue;
            char end[64];
            std::snprintf(end, sizeof end, " occluders %a %a %a", targets_[k].x, targets_[k].y,
                          targets_[k].z);
            cubes_[k] = shared_entry<OccluderCube>(
                caches.occluder_cubes, caches.list_key.empty() ? "" : caches.list_key + end,
                [&](OccluderCube& cube) { cube = OccluderCube(list, targets_[k], threads); });
        }
    }

    const OccluderCube* occluders(size_t k) const override { return cubes_[k].get(); }

    float lit(size_t k, const ShadowSample& at) const override {
        Ray ray;
        if (!shadow_ray(k, at, ray)) return 1.0f;
        return accel_->occluded(ray) ? 0.0f : 1.0f;
    }

    // Toward a point (every caster but a directional light), the rays of nearby samples end
    // at one point and the BVH tests them together (Accel::occluded_toward), 8 x 8 pixels at
    // a time; the answers are lit()'s. No virtual call a ray. (fill_masks leaves out the
    // samples the caster's occluder cube shows lit.)
    void lit_many(size_t k, const ShadowSample* samples, const uint32_t* at, size_t count,
                  float* out) const override {
        if (casters_[k].kind == ShadowCaster::Kind::Directional) {
            for (size_t m = 0; m < count; ++m) out[m] = lit(k, samples[at[m]]);
            return;
        }
        PointRays lanes;
        Ray rays[PointRays::kPacket];
        PrimitiveRange skip_of[PointRays::kPacket];  // each sample's (skip_for)
        PrimitiveRange skip[PointRays::kPacket];     // each ray's
        uint32_t slot[PointRays::kPacket];           // each sample's place in `out`
        uint32_t traced[PointRays::kPacket];         // each ray's sample in the packet
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
                skip[count_rays] = skip_of[r];
                traced[count_rays++] = static_cast<uint32_t>(r);
            }
            accel_->occluded_toward(targets_[k], rays, count_rays, blocked, skip);
            for (size_t r = 0; r < count_rays; ++r) out[slot[traced[r]]] = blocked[r] ? 0.0f : 1.0f;
            n = 0;
        };
        auto add = [&](size_t m) {
            const ShadowSample& sample = samples[at[m]];
            for (int c = 0; c < 3; ++c) {
                lanes.p[c][n] = sample.p[c];
                lanes.n[c][n] = sample.n[c];
            }
            skip_of[n] = skip_for(sample);
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
    /// The triangles a shadow ray from sample `at` cannot meet (Accel::occluded_toward's
    /// skip): those of the object it lies on when the ray leaves it (leaves_convex, from the
    /// side at.n, which faces the light: lit_many's samples face their caster; the ray starts
    /// in front of that side, shadow_origin). Else (the inside of a solid seen, or a sample of
    /// no known triangle), none.
    PrimitiveRange skip_for(const ShadowSample& at) const {
        // Instances drawn in place: a sample's triangle is one of the visible list, whose
        // numbers are not the BVH's.
        if (placed_) return {};
        const std::vector<PrimitiveRange>& objects = list_.objects;
        // The object holding the triangle: the last that starts at or before it.
        const auto after = std::upper_bound(
            objects.begin(), objects.end(), at.triangle,
            [](uint32_t triangle, const PrimitiveRange& r) { return triangle < r.first; });
        if (after == objects.begin()) return {};
        const auto k = static_cast<size_t>(after - objects.begin()) - 1;
        if (at.triangle >= objects[k].end || k >= list_.convex.size()) return {};
        return leaves_convex(list_.convex[k] != 0, list_.centroid[k], at.p, at.n)
                   ? objects[k]
                   : PrimitiveRange{};
    }

    /// The shadow ray from sample `at` to caster k (shadow_origin): to the caster's target,
    /// t in (0, 1), or toward a directional light without end. False when it is not finite
    /// (then the sample counts as lit).
    bool shadow_ray(size_t k, const ShadowSample& at, Ray& ray) const {
        const ShadowCaster& c = casters_[k];
        const vec3 wi = c.to_light(at.p);
        ray = Ray{shadow_origin(at.p, at.n, wi), wi, kInfinity};
        if (c.kind != ShadowCaster::Kind::Directional) {
            ray.d = targets_[k] - ray.o;  // to the caster
            ray.tmax = 1.0f;
        }
        return finite_ray(ray.o, ray.d);
    }

    /// Samples a triangle of the frame beyond which a cube that is not kept pays.
    static constexpr double kSamplesPerTriangle = 32.0;

    std::vector<vec3> targets_;                               // per caster: where its rays end
    std::vector<std::shared_ptr<const OccluderCube>> cubes_;  // per caster, or none
    std::shared_ptr<const BuiltGeometry> built_;              // the triangles and their BVH
    std::unique_ptr<Cutouts> cutouts_;
    std::unique_ptr<CutoutAccel> see_through_;
    const Accel* accel_ = nullptr;
    const TriangleList& list_;  // the frame's, which outlives its shadows
    bool placed_;               // the frame draws instances in place (FrameShading::placed)
};

}  // namespace

std::unique_ptr<ShadowTechniqueState> make_raytraced_shadows(const Scene& scene,
                                                             const TriangleList& list,
                                                             const FrameShading& f,
                                                             const FrameCaches& caches, int threads,
                                                             PassMemory*) {
    return std::make_unique<RaytracedShadows>(scene, list, f, caches, threads);
}

}  // namespace svetlo::raster
