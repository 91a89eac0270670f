// Alpha as holes for rays (docs/real-scenes.md, "Alpha"): one rule for every query that asks
// what a ray meets, in every engine that traces rays (Whitted, the path tracer, the
// rasterizer's ray-traced shadows, radiosity's visibility). A hit on a masked material whose
// coverage is below its cutoff, or on a blended one where a hash of the ray falls above its
// coverage, is not a hit: the ray goes on from just past it. The structures themselves (the
// BVHs, the grid, the octree, Embree) stay geometric; the queries loop over them, or ask the
// wide BVH's filtered any-hit query (Accel::occluded_if) to ask hole() at each triangle.
#pragma once

#include <memory>
#include <vector>

#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/geometry.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// The one rule: whether a surface of alpha `alpha` is a hole at a point with varyings `at`, with
/// `coin` uniform in [0, 1) for a blend (a hole with probability 1 - coverage). The coverage
/// is the texture's finest level, bilinear (a cutout's edge is as sharp as its texels).
bool alpha_hole(const Alpha& alpha, const Varyings& at, float coin,
                const std::vector<TextureImage>& textures);

/// The expected share of the surface that is there at `at`, over blend_coin's coins: 1 where
/// opaque, 0 or 1 for a mask, the coverage for a blend. What a light's emission is weighed by
/// where the light set samples a point of it (light_set.h).
float mean_cover(const Alpha& alpha, const Varyings& at, const std::vector<TextureImage>& textures);

/// A uniform number in [0, 1) from `key` (a ray's bits, a sample's place): a blend's coin.
float blend_coin(uint64_t key);

class Cutouts {
public:
    /// `materials` indexed by the geometry's material ids; textures the scene's.
    Cutouts(const Geometry& geometry, const std::vector<Material>& materials,
            const std::vector<TextureImage>& textures);

    /// Whether some material has a mask or a blend (else every hit is a hit).
    bool any() const { return any_; }
    /// Whether `hit` of `ray` falls in a hole: the ray passes through there.
    bool hole(const Ray& ray, const Hit& hit) const;

    /// The closest hit that is not a hole: `closest(ray, hit)` (a structure's closest-hit
    /// query) asked again from just past each hole, at most kMaxLayers times (then the ray is
    /// taken to pass). hit.t is measured along `ray`.
    template <class Closest>
    bool closest_solid(const Ray& ray, Hit& hit, Closest&& closest) const {
        if (!any_) return closest(ray, hit);
        Ray r = ray;
        for (int layer = 0; layer < kMaxLayers; ++layer) {
            Hit h;
            if (!closest(r, h)) return false;
            if (!hole(r, h)) {
                h.t += ray_offset(ray, r);
                hit = h;
                return true;
            }
            if (!past(ray, r, h)) return false;
        }
        return false;
    }

    /// Whether something solid lies on `ray` at 0 < t < ray.tmax in `accel` (over this
    /// geometry): its any-hit query asking hole() of each triangle it meets, where the
    /// structure has one (Accel::occluded_if) and only triangles can be holes; else its any-hit
    /// query, and where that meets something its closest hit that is not a hole.
    bool occluded_solid(const Ray& ray, const Accel& accel) const;
    /// Whether every primitive that can be a hole is a triangle (no shape of a material with
    /// alpha): the condition of the any-hit path above.
    bool holes_on_triangles_only() const { return holes_on_triangles_only_; }

    static constexpr int kMaxLayers = 256;

private:
    /// r moved to just past hit h (off its surface, along r.d), its tmax what is left of
    /// `ray`'s; false when nothing is left.
    bool past(const Ray& ray, Ray& r, const Hit& h) const;
    /// The t along `ray` of r's origin.
    static float ray_offset(const Ray& ray, const Ray& r) {
        return glm::dot(r.o - ray.o, ray.d) / glm::dot(ray.d, ray.d);
    }

    const Geometry& geometry_;
    const std::vector<Material>& materials_;
    const std::vector<TextureImage>& textures_;
    std::vector<char> active_;  // per material: a mask or a blend
    bool any_ = false;
    bool holes_on_triangles_only_ = true;
};

/// A structure whose queries see through the cutouts of `cutouts` (radiosity's visibility,
/// the rasterizer's ray-traced shadows); it refers to both, which must outlive it.
class CutoutAccel : public Accel {
public:
    CutoutAccel(const Accel& inner, const Cutouts& cutouts) : inner_(inner), cutouts_(cutouts) {}
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    size_t memory_bytes() const override { return inner_.memory_bytes(); }

private:
    const Accel& inner_;
    const Cutouts& cutouts_;
};

}  // namespace svetlo
