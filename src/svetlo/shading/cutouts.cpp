#include "svetlo/shading/cutouts.h"

#include <optional>

#include "svetlo/core/bit_cast.h"
#include "svetlo/core/rng.h"
#include "svetlo/shading/texture.h"

namespace svetlo {

namespace {

/// A blended surface's coin from the ray and the primitive it meets: the same for the same
/// ray whatever the thread (so the same seed gives the same image), different from ray to ray.
float ray_coin(const Ray& ray, uint32_t prim) {
    uint64_t h = mix64(prim);
    for (float c : {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z})
        h = mix64(h ^ svetlo::bit_cast<uint32_t>(c));
    return blend_coin(h);
}

}  // namespace

float blend_coin(uint64_t key) { return static_cast<float>(mix64(key) >> 40) * 0x1.0p-24f; }

namespace {

/// The coverage texel (or constant) at `at`: its red channel.
float coverage_at(const Alpha& alpha, const Varyings& at,
                  const std::vector<TextureImage>& textures) {
    return alpha.coverage.varies() ? eval_color(alpha.coverage, at, textures).r
                                   : alpha.coverage.value.r;
}

}  // namespace

bool alpha_hole(const Alpha& alpha, const Varyings& at, float coin,
                const std::vector<TextureImage>& textures) {
    if (!alpha.active()) return false;
    const float coverage = coverage_at(alpha, at, textures);
    return alpha.mode == AlphaMode::Mask ? coverage < alpha.cutoff : coin >= coverage;
}

float mean_cover(const Alpha& alpha, const Varyings& at,
                 const std::vector<TextureImage>& textures) {
    switch (alpha.mode) {
        case AlphaMode::Opaque:
            return 1.0f;
        case AlphaMode::Mask:
            return alpha_hole(alpha, at, 0.0f, textures) ? 0.0f : 1.0f;
        case AlphaMode::Blend:
            return std::clamp(coverage_at(alpha, at, textures), 0.0f, 1.0f);
    }
    return 1.0f;
}

Cutouts::Cutouts(const Geometry& geometry, const std::vector<Material>& materials,
                 const std::vector<TextureImage>& textures)
    : geometry_(geometry), materials_(materials), textures_(textures) {
    for (const Material& m : materials) {
        active_.push_back(m.alpha.active() ? 1 : 0);
        any_ = any_ || m.alpha.active();
    }
    // A CSG shape's leaves have materials of their own; an instance's primitives are the
    // prototypes' (the placed structure asks each prototype's: counted as shapes here).
    for (const AnalyticShape& shape : geometry.shapes) {
        if (shape.kind == ShapeKind::Csg || shape.material >= active_.size() ||
            active_[shape.material])
            holes_on_triangles_only_ = false;
    }
    if (!geometry.placements.empty()) holes_on_triangles_only_ = false;
}

bool Cutouts::hole(const Ray& ray, const Hit& hit) const {
    // A shape's material is its surface's (a CSG leaf's); a triangle's is stored.
    std::optional<SurfaceHit> surface;
    if (!geometry_.is_triangle(hit)) surface = geometry_.surface(ray, hit);
    const uint32_t material = surface ? surface->material : geometry_.material(hit);
    if (material >= active_.size() || !active_[material]) return false;
    const Alpha& alpha = materials_[material].alpha;
    Varyings at;
    if (alpha.coverage.varies()) {
        if (!surface) surface = geometry_.surface(ray, hit);
        at = surface->varyings();
    }
    return alpha_hole(alpha, at, alpha.mode == AlphaMode::Blend ? ray_coin(ray, hit.prim) : 0.0f,
                      textures_);
}

bool Cutouts::past(const Ray& ray, Ray& r, const Hit& h) const {
    const SurfaceHit s = geometry_.surface(r, h);
    r.o = offset_ray_origin(s.p, s.ng, r.d);
    r.tmax = ray.tmax - ray_offset(ray, r);
    return r.tmax > 0.0f;
}

bool CutoutAccel::intersect(const Ray& ray, Hit& hit) const {
    return cutouts_.closest_solid(ray, hit,
                                  [&](const Ray& r, Hit& h) { return inner_.intersect(r, h); });
}

bool Cutouts::occluded_solid(const Ray& ray, const Accel& accel) const {
    if (!any_) return accel.occluded(ray);
    if (holes_on_triangles_only_ && accel.filters_hits()) {
        const auto solid = [](const void* self, const Ray& r, const Hit& h) {
            return !static_cast<const Cutouts*>(self)->hole(r, h);
        };
        return accel.occluded_if(ray, HitFilter{solid, this});
    }
    // A ray that meets nothing meets nothing solid: holes are looked for only where it does.
    if (!accel.occluded(ray)) return false;
    Hit hit;
    return closest_solid(ray, hit, [&](const Ray& r, Hit& h) { return accel.intersect(r, h); });
}

bool CutoutAccel::occluded(const Ray& ray) const { return cutouts_.occluded_solid(ray, inner_); }

}  // namespace svetlo
