// Caustic photons (Jensen, "Global Illumination using Photon Maps", EGWR 1996): paths from the
// lights through delta surfaces (mirrors, glass, the mirror and transmission parts of Phong)
// to a surface with a non-delta BSDF, L S+ D in Heckbert's notation. A path tracer cannot
// find them from a point, spot or directional light at all, and finds them slowly from a
// small area light. The radiance at a point is the density estimate
//
//   L(x, wo) = 1 / (pi r^2) sum over photons within r of f(wo, wi_p) Phi_p,
//
// Phi_p in W. Each pass of the path tracer builds a new map with a smaller radius, r_{k+1}^2 =
// r_k^2 (k + 1 + alpha) / (k + 2): probabilistic progressive photon mapping (Knaus and
// Zwicker, "Progressive Photon Mapping: A Probabilistic Approach", TOG 2011), whose average
// over passes converges to the exact caustic. Photons are aimed at the bounding spheres of the
// objects with delta materials, as Jensen's projection maps do, and weighted by the pdf of
// that aim, so none is wasted on the diffuse rest.
#pragma once

#include <cstdint>
#include <vector>

#include "svetlo/pt/spectrum.h"
#include "svetlo/rt/rt_scene.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

class CausticPhotons {
public:
    /// Reads render.caustics and render.photons; `diameter` is the scene's, for the default
    /// radius and the directional lights' photons.
    CausticPhotons(const RtScene& rt, const WavelengthWeights& wavelengths, float diameter);

    /// There are lights that send photons and delta objects to aim them at.
    bool active() const { return !emitters_.empty() && !targets_.empty(); }
    /// Lights with area send photons too (render.caustics = photons).
    bool covers_area_lights() const { return covers_area_lights_; }

    /// Traces pass `pass`'s photons on `threads` threads and builds its lookup grid. Passes
    /// are built in order, from 0: each shrinks the radius of the one before.
    void build(int pass, int threads);
    /// The radius of pass `pass` alone, after pass - 1's, without tracing its photons: how a
    /// render resumed from a checkpoint catches up with the passes it did not build.
    void shrink_radius(int pass);
    /// The caustic radiance toward wo at p (frame and BSDF of the point).
    Color radiance(vec3 p, const ShadingFrame& frame, vec3 wo, const Bsdf& bsdf) const;

    uint64_t rays() const { return rays_; }
    size_t stored() const { return photons_.size(); }
    float radius() const { return radius_; }

private:
    struct Photon {
        vec3 p;       // where it landed
        vec3 wi;      // unit, back toward where it came from
        vec3 n;       // the surface's geometric normal on the side it arrived from
        Color power;  // W, divided by the photons emitted in the pass
    };
    struct Target {
        vec3 center;
        float radius;
    };
    struct Emitter {
        int source;              // index in the light set's sources
        float probability;       // of being chosen for a photon
        bool spot_cone = false;  // a spot light narrower than the targets: photons fill its
                                 // cone instead of being aimed at the targets
    };

    /// Traces photon `index` of `count`, appending what it leaves to `out` while it holds
    /// fewer than `cap`.
    void trace_photon(uint64_t index, int pass, int count, std::vector<Photon>& out, size_t cap,
                      uint64_t& rays) const;
    /// The ray of a photon from a punctual light and its power (W, before the emitter's
    /// probability and the pass's count): a directional light's from a disc across a target,
    /// a point or spot light's aimed at the targets (or filling the spot's cone).
    Ray punctual_photon(const Light& light, bool spot_cone, vec2 u1, float u_pick,
                        Color& power) const;
    /// A direction from x toward a target, chosen uniformly among them, and the pdf of the
    /// mixture of their cones.
    vec3 aim(vec3 x, vec2 u, float u_pick) const;
    /// A direction uniform in the cone about `axis` with 1 - cos(half-angle) = one_minus_cos.
    static vec3 in_cone(vec3 axis, float one_minus_cos, vec2 u);
    float aim_pdf(vec3 x, vec3 w) const;
    size_t bucket(glm::ivec3 cell) const;

    const RtScene& rt_;
    const WavelengthWeights& wavelengths_;
    float diameter_;
    bool covers_area_lights_ = false;
    std::vector<Target> targets_;
    std::vector<Emitter> emitters_;

    double radius2_ = 0.0;  // this pass's radius, squared
    float radius_ = 0.0f;
    uint64_t rays_ = 0;
    std::vector<Photon> photons_;         // sorted by bucket
    std::vector<uint32_t> bucket_start_;  // per bucket, its first photon; one more at the end
    float cell_ = 1.0f;                   // grid cell side: twice the radius
};

}  // namespace svetlo
