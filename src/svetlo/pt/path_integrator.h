// The path tracer's estimator of the radiance along one camera ray (Kajiya 1986): a random
// walk through the BSDFs' sample functions, with next-event estimation toward one light,
// chosen by power (light_selection.h), at every non-delta vertex, the two strategies (light
// sampling, BSDF sampling) combined by multiple importance sampling with the power heuristic (Veach
// and Guibas 1995), the background as a uniform environment light sampled like the others, and
// Russian roulette from the fourth vertex on. render.max_depth bounds the bounces after the first
// hit: 0 is direct light only. Caustics that paths cannot find come from a photon map
// (caustic_photons.h); dispersive glass gives the path a wavelength (spectrum.h). With a
// guiding field (guiding_field.h), a bounce off a surface without delta lobes is drawn from
// the BSDF or the field, one sample of their mixture, and the mixture's pdf is the one MIS
// weighs against the lights.
#pragma once

#include <array>
#include <cstdint>

#include "svetlo/core/rng.h"
#include "svetlo/pt/caustic_photons.h"
#include "svetlo/pt/guiding_field.h"
#include "svetlo/pt/light_selection.h"
#include "svetlo/pt/path_observer.h"
#include "svetlo/pt/sobol_sampler.h"
#include "svetlo/pt/spectrum.h"
#include "svetlo/rt/rt_scene.h"
#include "svetlo/scene/renderer.h"

namespace svetlo {

class PathIntegrator {
public:
    /// `photons` may be null (no photon map this pass).
    PathIntegrator(const RtScene& rt, const LightSelection& selection,
                   const WavelengthWeights& wavelengths, const CausticPhotons* photons);

    /// The radiance along `ray`, linear RGB, W/(m^2 sr). With `aov`, also the first hit's
    /// AOVs; light 0's visibility draws from `aov_rng`, so AOVs never change the image.
    Color radiance(Ray ray, SobolSampler& sampler, AovSample* aov, Rng* aov_rng);

    /// Draws guided bounces from `field` (null: none); with `train`, records what each of
    /// them brings back into it.
    void guide(GuidingField* field, bool train) {
        guide_ = field;
        train_ = field && train;
    }

    uint64_t rays = 0;  // every ray traced, shadow rays included
    int bounces = 0;    // of the last path: the BSDF-sampled rays it traced (path_depth)
    PathObserver* observer = nullptr;  // svetlo trace's (path_observer.h), when set

private:
    /// What radiance() keeps of the vertex before the one it is at: how its BSDF sample was
    /// drawn (MIS weighs what that sample meets by it) and where. The camera counts like a
    /// delta vertex: what it sees directly counts in full.
    struct PreviousVertex {
        bool delta = true;
        float pdf = 0.0f;       // its BSDF sample's pdf (non-delta lobes)
        int light_samples = 1;  // its light samples per light with area
        vec3 p{0.0f}, ng{0.0f};
        bool after_lobes = false;  // a non-delta vertex lies behind: caustic paths start there
    };
    /// The background's radiance along a ray that left the scene, MIS-weighted against the
    /// environment's own sampling at the previous vertex.
    Color escaped(const Ray& ray, const PreviousVertex& prev, Color beta);
    /// The emission of the surface met, seen from its front, MIS-weighted against next-event
    /// estimation at the previous vertex (none on the photon map's paths).
    Color emitted(const Hit& hit, const SurfaceHit& sh, const ShadingFrame& frame, const Bsdf& bsdf,
                  const PreviousVertex& prev, Color beta);
    /// Next-event estimation at a vertex with lobes, added to L: one light (`n` samples of it
    /// when it has area), the environment, and the caustic photons.
    void add_direct_light(const Bsdf& bsdf, const SurfaceHit& sh, const ShadingFrame& frame,
                          vec3 wo, int n, const std::array<vec2, 4>& u, SobolSampler& sampler,
                          Guide guide, Color beta, Color& L);
    /// MIS weight of an emitter met by BSDF sampling from `from` (pdf `pdf_bsdf`), where
    /// next-event estimation took `light_samples` samples per light with area.
    float emitter_weight(const Hit& hit, vec3 from, float pdf_bsdf, int light_samples, vec3 p,
                         vec3 ng) const;
    /// Next-event estimation of one light, chosen by selection_, at p: `n` samples of it
    /// when it has area.
    /// `choice` picks the light (x) and its first sample's primitive (y), `u_first` the first
    /// sample's point; further samples draw from `sampler`.
    /// `guide` is the vertex's guiding distribution, or empty.
    Color one_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo, int n,
                    vec2 choice, vec2 u_first, SobolSampler& sampler, Guide guide);
    /// Next-event estimation of the background at p: a cosine-weighted direction about ng,
    /// drawn from u.
    Color environment_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo, vec2 u,
                            Guide guide);
    /// Records, for every guided vertex of the path just ended, the radiance its bounce
    /// brought back (what the image gained after it, over its throughput) over its pdf.
    void record_path(Color L);

    const RtScene& rt_;
    const LightSelection& selection_;
    const Scene& scene_;
    const WavelengthWeights& wavelengths_;
    const CausticPhotons* photons_;
    bool environment_;  // the background is not black: it is a light
    // The map's density for its light samples: compensated where MIS pairs them with the
    // BSDF's draws (environment.h), its importance where they are alone.
    EnvironmentDensity env_density_;
    GuidingField* guide_ = nullptr;
    bool train_ = false;

    /// A guided vertex of the path being followed, while training.
    struct GuidedVertex {
        Guide where;  // its region and facing
        vec3 wi;
        Color beta;      // the throughput after its bounce
        Color L_before;  // the radiance gathered before its bounce
        float pdf;       // of the bounce's direction
    };
    static constexpr int kMaxGuidedVertices = 32;
    std::array<GuidedVertex, kMaxGuidedVertices> guided_;
    int guided_count_ = 0;
};

}  // namespace svetlo
