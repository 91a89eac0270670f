#include "svetlo/pt/path_integrator.h"

#include "svetlo/core/sampling.h"
#include "svetlo/pt/mis.h"
#include "svetlo/rt/shadow_rays.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/direct_light.h"

namespace svetlo {

namespace {

/// The bounce from which Russian roulette may end a path, and the highest survival chance.
/// A path survives with probability min(kMaxSurvival, sqrt(max(beta))): the square root (as
/// Cycles has it) ends paths later than max(beta) did, 6 % more time for 15-25 % less
/// variance on the Cornell box (docs/path.md).
constexpr int kRouletteDepth = 3;
constexpr float kMaxSurvival = 0.95f;

/// Whether a bounce off `bsdf` may be guided: it has lobes and nothing but lobes.
bool guidable(const Bsdf& bsdf) {
    return bsdf.has_lobes() && is_black(bsdf.reflect) && is_black(bsdf.transmit);
}

/// The pdf per steradian of a guided bounce, from its BSDF's and its guide's: their
/// mixture, kGuidingBsdfFraction of the BSDF's.
float mixture_pdf(float bsdf_pdf, float guide_pdf) {
    constexpr float a = kGuidingBsdfFraction;
    return a * bsdf_pdf + (1.0f - a) * guide_pdf;
}

/// The pdf per steradian of a bounce to wi: the BSDF's, or with a guiding distribution,
/// the mixture's.
float scatter_pdf(const Bsdf& bsdf, vec3 n, vec3 wo, vec3 wi, Guide guide) {
    const float bsdf_pdf = pdf_bsdf(bsdf, n, wo, wi);
    return guide ? mixture_pdf(bsdf_pdf, guide.pdf(wi)) : bsdf_pdf;
}

/// One sample of the mixture of the BSDF and the guiding distribution `guide`: u_pick
/// chooses the BSDF below kGuidingBsdfFraction, and its rescaled value picks the lobe.
BsdfSample sample_guided(const Bsdf& bsdf, const ShadingFrame& frame, vec3 wo, Guide guide, vec2 u,
                         float u_pick) {
    constexpr float a = kGuidingBsdfFraction;
    BsdfSample s;
    float guide_pdf = 0.0f;
    if (u_pick < a) {
        s = sample_bsdf(bsdf, frame.ns, wo, frame.front, u, std::min(u_pick / a, 0x1.fffffep-1f));
        if (!s.valid()) return s;
        guide_pdf = guide.pdf(s.wi);
    } else {
        s.wi = guide.sample(u, guide_pdf);
        s.f = eval_bsdf(bsdf, frame.ns, wo, s.wi);
    }
    s.pdf = mixture_pdf(pdf_bsdf(bsdf, frame.ns, wo, s.wi), guide_pdf);
    s.weight = s.pdf > 0.0f ? s.f * (std::abs(glm::dot(frame.ns, s.wi)) / s.pdf) : Color(0.0f);
    s.delta = false;
    return s;
}

}  // namespace

PathIntegrator::PathIntegrator(const RtScene& rt, const LightSelection& selection,
                               const WavelengthWeights& wavelengths, const CausticPhotons* photons)
    : rt_(rt),
      selection_(selection),
      scene_(rt.scene()),
      wavelengths_(wavelengths),
      photons_(photons),
      environment_(!rt.environment().is_black()),
      env_density_(rt.scene().render.mis == MisMode::Power ? EnvironmentDensity::Compensated
                                                           : EnvironmentDensity::Importance) {}

float PathIntegrator::emitter_weight(const Hit& hit, vec3 from, float pdf_bsdf, int light_samples,
                                     vec3 p, vec3 ng) const {
    int source = rt_.light_source_of(hit);
    if (source < 0) return 1.0f;  // a glowing CSG or implicit surface: no light to sample
    const LightSet::Source& s = rt_.lights().sources()[static_cast<size_t>(source)];
    // As one_light draws it: the light's choice, then its samples.
    float pdf_light = selection_.probability(static_cast<size_t>(source)) *
                      rt_.lights().pdf(s, from, p, ng, rt_.light_prim_of(hit)) *
                      static_cast<float>(light_samples);
    return bsdf_weight(scene_.render.mis, pdf_bsdf, pdf_light);
}

Color PathIntegrator::one_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo, int n,
                                vec2 choice, vec2 u_first, SobolSampler& sampler, Guide guide) {
    if (selection_.empty()) return Color(0.0f);
    const LightSet& lights = rt_.lights();
    float chosen;
    const LightSet::Source& source = lights.sources()[selection_.pick(choice.x, chosen)];
    if (source.delta) n = 1;
    Color sum(0.0f);
    for (int k = 0; k < n; ++k) {
        // Further samples draw the primitive's pick, then the point: in two statements, so
        // that every compiler draws them in this order (as arguments of one call, GCC drew
        // them right to left and clang left to right: another image in the browser's build).
        const float u_pick = k == 0 ? choice.y : sampler.next_float();
        const vec2 u_point = k == 0 ? u_first : sampler.next_2d();
        LightSample s = source.delta
                            ? lights.sample(source, p, vec2(0.0f), 0.0f)
                            : lights.sample(source, p, stratified_sample(k, n, u_point), u_pick);
        Color c = unoccluded_light(bsdf, frame, wo, s);  // f E cos, the lighting core's
        if (is_black(c)) {
            if (observer)
                observer->light_sample(p, frame.ng, s.wi, s.distance, 0.0f, 0.0f, 0.0f, Color(0.0f),
                                       1.0f,
                                       "brings no light here (below the surface): not traced");
            continue;
        }
        float w = 1.0f;
        if (!s.delta) {
            w = light_weight(scene_.render.mis, static_cast<float>(n) * chosen * s.pdf,
                             scatter_pdf(bsdf, frame.ns, wo, s.wi, guide));
        }
        const bool blocked = w == 0.0f || shadow_blocked(rt_, p, frame.ng, s, rays);
        if (observer) {
            const float scale = 1.0f / (static_cast<float>(n) * chosen);
            observer->light_sample(p, frame.ng, s.wi, s.distance,
                                   s.delta ? chosen : n * chosen * s.pdf, w, blocked ? 0.0f : 1.0f,
                                   blocked ? Color(0.0f) : c, w * scale,
                                   w == 0.0f ? "MIS weight 0: not traced" : nullptr);
        }
        if (blocked) continue;
        sum += c * w;
    }
    return sum / (static_cast<float>(n) * chosen);
}

Color PathIntegrator::environment_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame,
                                        vec3 wo, vec2 u, Guide guide) {
    if (scene_.render.mis == MisMode::BsdfOnly) return Color(0.0f);
    const Environment& env = rt_.environment();
    // A map: a direction by the map's importance; the uniform background: by the cosine
    // about the geometric normal.
    vec3 wi;
    float pdf;
    Color Le = scene_.render.background;
    if (env.is_map()) {
        const EnvironmentSample s = env.sample(u, env_density_);
        wi = s.wi;
        pdf = glm::dot(frame.ng, wi) > 0.0f ? s.pdf : 0.0f;
        Le = s.radiance;
    } else {
        wi = Frame::from_normal(frame.ng).to_world(sample_cosine_hemisphere(u));
        pdf = glm::dot(frame.ng, wi) * kInvPi;
    }
    float cos_theta = glm::dot(frame.ns, wi);
    if (cos_theta <= 0.0f || !(pdf > 0.0f)) return Color(0.0f);
    Color f = eval_bsdf(bsdf, frame.ns, wo, wi);
    if (is_black(f)) return Color(0.0f);
    ++rays;
    const bool blocked = rt_.occluded(Ray{offset_ray_origin(p, frame.ng, wi), wi, kInfinity});
    float w = light_weight(scene_.render.mis, pdf, scatter_pdf(bsdf, frame.ns, wo, wi, guide));
    const Color c = blocked ? Color(0.0f) : f * Le * (cos_theta * w / pdf);
    if (observer)
        observer->light_sample(p, frame.ng, wi, kInfinity, pdf, w, blocked ? 0.0f : 1.0f, c, 1.0f,
                               "the background");
    return c;
}

// escaped, emitted and add_direct_light are inlined into radiance(), their one caller: the
// path loop pays no call per vertex.
[[gnu::always_inline]] inline Color PathIntegrator::escaped(const Ray& ray,
                                                            const PreviousVertex& prev,
                                                            Color beta) {
    if (!environment_) return Color(0.0f);
    const Environment& env = rt_.environment();
    const Color Le = env.radiance(ray.d);
    float pdf_env = env.is_map() ? env.pdf(ray.d, env_density_)
                                 : std::max(0.0f, glm::dot(prev.ng, ray.d)) * kInvPi;
    float w = prev.delta ? 1.0f : bsdf_weight(scene_.render.mis, prev.pdf, pdf_env);
    if (observer) observer->background(beta * Le * w, w);
    return beta * Le * w;
}

[[gnu::always_inline]] inline Color PathIntegrator::emitted(const Hit& hit, const SurfaceHit& sh,
                                                            const ShadingFrame& frame,
                                                            const Bsdf& bsdf,
                                                            const PreviousVertex& prev,
                                                            Color beta) {
    if (!frame.front || is_black(bsdf.emission)) return Color(0.0f);
    // With every light sending photons, the paths that reach an emitter through delta
    // vertices after a non-delta one are the photon map's (no double counting).
    bool photon_path = prev.delta && prev.after_lobes && photons_ &&
                       photons_->covers_area_lights() && rt_.light_source_of(hit) >= 0;
    if (photon_path) return Color(0.0f);
    float w = prev.delta
                  ? 1.0f
                  : emitter_weight(hit, prev.p, prev.pdf, prev.light_samples, sh.p, frame.ng);
    if (observer) observer->emitted(beta * bsdf.emission * w, w);
    return beta * bsdf.emission * w;
}

[[gnu::always_inline]] inline void PathIntegrator::add_direct_light(
    const Bsdf& bsdf, const SurfaceHit& sh, const ShadingFrame& frame, vec3 wo, int n,
    const std::array<vec2, 4>& u, SobolSampler& sampler, Guide guide, Color beta, Color& L) {
    L += beta * one_light(bsdf, sh.p, frame, wo, n, u[0], u[1], sampler, guide);
    if (environment_)
        L += beta * environment_light(bsdf, sh.p, frame, wo, sampler.next_2d(), guide);
    if (photons_) {
        const Color caustic = photons_->radiance(sh.p, frame, wo, bsdf);
        L += beta * caustic;
        if (observer) observer->photons(caustic, beta * caustic);
    }
}

Color PathIntegrator::radiance(Ray ray, SobolSampler& sampler, AovSample* aov, Rng* aov_rng) {
    const RenderSettings& settings = scene_.render;
    ray.d = glm::normalize(ray.d);  // hit.t is then the distance (the depth AOV)
    Color L(0.0f), beta(1.0f);
    PreviousVertex prev;
    Color medium(0.0f);   // the absorption of the object the ray travels inside
    float lambda = 0.0f;  // nm, picked at the first dispersive interface
    int depth = 0;
    for (;; ++depth) {
        ++rays;
        Hit hit;
        const bool met = rt_.intersect(ray, hit);
        if (observer)
            observer->ray(ray, depth, met ? hit.t : kInfinity, beta, prev.pdf, prev.delta);
        beta *= transmittance(medium, met ? hit.t : kInfinity);
        if (!met) {
            L += escaped(ray, prev, beta);
            break;
        }
        SurfaceHit sh = rt_.surface(ray, hit);
        Bsdf bsdf = rt_.bsdf(sh.material, sh.varyings());
        const vec3 wo = -ray.d;
        const ShadingFrame frame = make_shading_frame(sh.ng, sh.ns, wo);
        bsdf.coat_normal = seen_coat_normal(sh.coat_ns, frame, wo);
        if (observer) observer->vertex(sh, frame, depth, beta);
        if (aov && depth == 0) {
            aov->depth = hit.t;
            aov->normal = frame.ns;
            aov->albedo = albedo_of(bsdf);
            if (aov_rng) {
                aov->visibility =
                    light0_visibility(rt_, sh.p, frame.ng, settings.light_samples, *aov_rng, rays);
            }
        }
        L += emitted(hit, sh, frame, bsdf, prev, beta);
        if (depth > settings.max_depth) break;

        // The vertex's sample values, four pairs: the light and its first sample's primitive
        // (stratified together), the light sample's point, the BSDF's direction, and its lobe
        // with the roulette. Further light samples and the background's draw after them.
        const std::array<vec2, 4> u = sampler.next_8();
        const bool guided = guide_ && guidable(bsdf);
        const Guide guide = guided ? guide_->at(sh.p, frame.ng) : Guide{};
        if (bsdf.has_lobes()) {
            // render.light_samples at the first hit, where direct light shows most; one
            // sample deeper, where the path's own spread averages it out.
            prev.light_samples = depth == 0 ? settings.light_samples : 1;
            add_direct_light(bsdf, sh, frame, wo, prev.light_samples, u, sampler, guide, beta, L);
        }

        if (bsdf.model == Bsdf::Model::Dielectric && bsdf.abbe > 0.0f) {
            if (lambda == 0.0f) {  // the path becomes one wavelength's
                lambda = WavelengthWeights::lambda_of(sampler.next_float());
                beta *= wavelengths_.weight(lambda);
            }
            bsdf.ior = cauchy_ior(bsdf.ior, bsdf.abbe, lambda);
        }
        const BsdfSample bs = guide ? sample_guided(bsdf, frame, wo, guide, u[2], u[3].x)
                                    : sample_bsdf(bsdf, frame.ns, wo, frame.front, u[2], u[3].x);
        if (!bs.valid()) break;
        // A reflection that leaves below the geometric surface would leak light through it.
        bool transmission = glm::dot(frame.ns, bs.wi) < 0.0f;
        if (!transmission && glm::dot(frame.ng, bs.wi) <= 0.0f) break;
        if (transmission) medium = medium_after(bsdf, frame.front);
        beta *= bs.weight;
        if (is_black(beta)) break;
        if (train_ && guided && guided_count_ < kMaxGuidedVertices)
            guided_[static_cast<size_t>(guided_count_++)] = {guide, bs.wi, beta, L, bs.pdf};
        prev.delta = bs.delta;
        prev.pdf = bs.pdf;
        prev.p = sh.p;
        prev.ng = frame.ng;  // the environment's sampling about it (environment_light)
        prev.after_lobes = prev.after_lobes || !bs.delta;
        ray = Ray{offset_ray_origin(sh.p, frame.ng, bs.wi), bs.wi, kInfinity};
        if (depth + 1 >= kRouletteDepth) {
            float survive = std::min(kMaxSurvival, std::sqrt(max_component(beta)));
            if (observer) observer->roulette(survive, u[3].y >= survive);
            if (u[3].y >= survive) break;
            beta /= survive;
        }
    }
    bounces = depth;  // every exit leaves depth at the BSDF-sampled rays traced
    if (train_) record_path(L);
    return L;
}

void PathIntegrator::record_path(Color L) {
    for (int k = 0; k < guided_count_; ++k) {
        const GuidedVertex& v = guided_[static_cast<size_t>(k)];
        // The incident radiance along the bounce, per channel (L - L_before) / beta: the mean
        // of the channels the throughput carries.
        const Color gained = L - v.L_before;
        float sum = 0.0f;
        int channels = 0;
        for (int c = 0; c < 3; ++c) {
            if (!(v.beta[c] > 0.0f)) continue;
            sum += gained[c] / v.beta[c];
            ++channels;
        }
        const float incident = channels ? std::max(0.0f, sum / static_cast<float>(channels)) : 0.0f;
        guide_->record(v.where, v.wi, incident / v.pdf);
    }
    guided_count_ = 0;
}

}  // namespace svetlo
