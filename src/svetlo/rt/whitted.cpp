#include "svetlo/rt/whitted.h"

#include <atomic>
#include <chrono>
#include <optional>

#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"
#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/rt/camera.h"
#include "svetlo/rt/rt_scene.h"
#include "svetlo/rt/shadow_rays.h"
#include "svetlo/rt/whitted_observer.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/direct_light.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

namespace {

/// Branches whose weight falls below this are not traced: Hall and Greenberg's adaptive
/// tree-depth control ("A Testbed for Realistic Image Synthesis", IEEE CG&A 1983). It drops
/// contributions under 1e-5 of the pixel's radiance scale.
constexpr float kMinBranchWeight = 1e-5f;

/// Where a ray sits in svetlo trace's tree: its kind, the ray it branches from, and the product
/// of the weights between it and the camera.
struct Branch {
    const char* kind = "camera";
    int parent = -1;
    Color to_pixel{1.0f};
    Color medium{0.0f};  // the absorption of the object the ray travels inside
};

class Tracer {
public:
    Tracer(const RtScene& rt, bool want_visibility)
        : rt_(rt), scene_(rt.scene()), want_visibility_(want_visibility) {}

    uint64_t rays = 0;
    uint64_t nonfinite = 0;  // camera samples dropped for a radiance that is not finite
    Rng* aov_rng = nullptr;  // the visibility AOV's own stream, so AOVs never change the image
    WhittedObserver* observer = nullptr;  // svetlo trace's (whitted_observer.h), when set

    Color trace(const Ray& ray, int depth, float weight, Rng& rng, AovSample* aov,
                const Branch& branch = {}) {
        ++rays;
        Hit hit;
        const bool met = rt_.intersect(ray, hit);
        const int self = observer ? observer->ray(ray, depth, branch.kind, branch.parent,
                                                  branch.to_pixel, met ? hit.t : kInfinity)
                                  : -1;
        // What the medium the ray crosses leaves of what it meets (Beer-Lambert).
        const Color kept =
            transmittance(branch.medium, met ? hit.t * glm::length(ray.d) : kInfinity);
        if (is_black(kept)) return Color(0.0f);
        return kept * shade(ray, hit, met, self, depth, weight, rng, aov, branch);
    }

private:
    /// What ray `ray` sees at `hit` (or beyond everything, `met` false).
    Color shade(const Ray& ray, const Hit& hit, bool met, int self, int depth, float weight,
                Rng& rng, AovSample* aov, const Branch& branch) {
        if (!met) {  // what comes from far away: the environment map or the background
            const Color Le = rt_.environment().radiance(glm::normalize(ray.d));
            if (observer) observer->adds(self, branch.to_pixel * Le);
            return Le;
        }
        SurfaceHit sh = rt_.surface(ray, hit);
        Bsdf bsdf = rt_.bsdf(sh.material, sh.varyings());
        vec3 wo = -glm::normalize(ray.d);
        const ShadingFrame frame = make_shading_frame(sh.ng, sh.ns, wo);
        bsdf.coat_normal = seen_coat_normal(sh.coat_ns, frame, wo);
        const bool front = frame.front;
        const vec3 ng = frame.ng, ns = frame.ns;
        if (observer) observer->hit(self, sh, ns, front);

        if (aov) {
            aov->depth = hit.t * glm::length(ray.d);
            aov->normal = ns;
            aov->albedo = albedo_of(bsdf);
            if (want_visibility_) {
                aov->visibility =
                    light0_visibility(rt_, sh.p, ng, scene_.render.light_samples, *aov_rng, rays);
            }
        }

        Color L = emitted_and_ambient(bsdf, frame, scene_.render.ambient);
        if (observer) observer->adds(self, branch.to_pixel * L);
        L += direct_light(
            rt_.lights(), bsdf, sh.p, frame, wo,
            StratifiedLightSampling{rt_.lights(), rng, scene_.render.light_samples},
            [&](size_t index, const LightSample& s) {
                const float v = shadow_blocked(rt_, sh.p, ng, s, rays) ? 0.0f : 1.0f;
                if (observer) {
                    const LightSet::Source& source = rt_.lights().sources()[index];
                    observer->shadow_ray(
                        self, depth, sh.p, ng, s.wi, s.distance, source.light_index, v,
                        unoccluded_light(bsdf, frame, wo, s),
                        source.delta ? 1.0f : static_cast<float>(scene_.render.light_samples),
                        branch.to_pixel);
                }
                return v;
            });
        if (rt_.environment().is_map() && bsdf.has_lobes())
            L += bsdf.occlusion * environment_light(bsdf, sh.p, frame, wo, rng);
        if (depth >= scene_.render.max_depth) return L;
        return L + recurse(bsdf, sh.p, frame, wo, self, depth, weight, rng, branch);
    }

    /// The rays the surface sends on (the recursion's part of L): mirrors, glass, Phong's
    /// `reflect` and `transmit`, and a Cook-Torrance surface's transmission, each traced with
    /// its weight.
    Color recurse(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo, int self, int depth,
                  float weight, Rng& rng, const Branch& branch) {
        const bool front = frame.front;
        const vec3 ng = frame.ng, ns = frame.ns;
        Color L(0.0f);
        auto follow = [&](Color scale, vec3 dir, const char* kind, float fresnel) {
            float w = weight * max_component(scale);
            if (w < kMinBranchWeight) return Color(0.0f);
            Ray next{offset_ray_origin(p, ng, dir), dir, kInfinity};
            // Through the surface, the ray enters (or leaves) the object's medium.
            const bool through = glm::dot(dir, ng) < 0.0f;
            const Branch next_branch{kind, self, branch.to_pixel * scale,
                                     through ? medium_after(bsdf, front) : branch.medium};
            if (observer && fresnel >= 0.0f) observer->fresnel(fresnel);
            return scale * trace(next, depth + 1, w, rng, nullptr, next_branch);
        };
        // The ideal transmitted part of weight `scale`: refracted at the material's ior; under
        // total internal reflection it reflects.
        auto transmit = [&](Color scale) {
            const float eta = front ? bsdf.ior : 1.0f / bsdf.ior;
            vec3 wt;
            const bool tir = !refract(wo, ns, eta, wt);
            if (tir) wt = reflect(wo, ns);
            return follow(scale, wt, tir ? "reflect" : "refract", -1.0f);
        };
        switch (bsdf.model) {
            case Bsdf::Model::Mirror:
                L += follow(bsdf.reflect, reflect(wo, ns), "reflect", -1.0f);
                break;
            case Bsdf::Model::Dielectric: {
                // Entering when we hit the outside; eta = n_transmitted / n_incident.
                float eta = front ? bsdf.ior : 1.0f / bsdf.ior;
                float fr = fresnel_dielectric(glm::dot(ns, wo), eta);
                vec3 wt;
                if (fr < 1.0f && refract(wo, ns, eta, wt))
                    L += follow(Color(1.0f - fr), wt, "refract", 1.0f - fr);
                else
                    fr = 1.0f;  // total internal reflection
                L += follow(Color(fr), reflect(wo, ns), "reflect", fr);
                break;
            }
            case Bsdf::Model::Phong:
            case Bsdf::Model::BlinnPhong: {
                if (!is_black(bsdf.reflect))
                    L += follow(bsdf.reflect, reflect(wo, ns), "reflect", -1.0f);
                if (!is_black(bsdf.transmit)) L += transmit(bsdf.transmit);
                break;
            }
            case Bsdf::Model::CookTorrance:  // KHR_materials_transmission
                if (rough_transmission(bsdf)) {
                    // Rough: one direction drawn from the BSDF, followed where it passes through
                    // the transmitted lobe (a refraction through a GGX microfacet, Walter et al.
                    // 2007, or its share reflected totally), by its weight f |cos| / pdf, the
                    // lobe's probability in it; the reflecting lobes are the direct light's.
                    const BsdfSample b =
                        sample_bsdf(bsdf, ns, wo, front, rng.next_2d(), rng.next_float());
                    if (b.valid() && b.delta)
                        L += follow(b.weight, b.wi,
                                    glm::dot(b.wi, ng) < 0.0f ? "refract" : "reflect", -1.0f);
                } else if (!is_black(bsdf.transmit)) {
                    L += transmit(transmitted_weight(bsdf, glm::dot(ns, wo)));
                }
                break;
            default:
                break;
        }
        return L;
    }

private:
    /// The environment map as a light (docs/whitted.md): render.light_samples directions drawn
    /// by the map's compensated importance (environment.h) and as many by the BSDF, stratified,
    /// each with its shadow ray, combined by the power heuristic (Veach and Guibas 1995): the
    /// map's importance finds its
    /// bright texels, the BSDF's a glossy lobe's narrow peak, which the map's alone found
    /// once in many thousand draws (a smooth surface's reflection was fireflies).
    Color environment_light(const Bsdf& bsdf, vec3 p, const ShadingFrame& frame, vec3 wo,
                            Rng& rng) {
        const Environment& env = rt_.environment();
        const int n = std::max(1, scene_.render.light_samples);
        // Whether the map is seen toward wi: above both normals and not shadowed.
        const auto reaches = [&](vec3 wi) {
            if (glm::dot(frame.ns, wi) <= 0.0f || glm::dot(frame.ng, wi) <= 0.0f) return false;
            ++rays;
            return !rt_.occluded(Ray{offset_ray_origin(p, frame.ng, wi), wi, kInfinity});
        };
        Color sum(0.0f);
        for (int k = 0; k < n; ++k) {
            const EnvironmentSample s =
                env.sample(stratified_sample(k, n, rng.next_2d()), EnvironmentDensity::Compensated);
            if (s.pdf > 0.0f) {
                const Color f = eval_bsdf(bsdf, frame.ns, wo, s.wi);
                if (!is_black(f) && reaches(s.wi))
                    sum += f * s.radiance *
                           (glm::dot(frame.ns, s.wi) / s.pdf *
                            power_heuristic(s.pdf, pdf_bsdf(bsdf, frame.ns, wo, s.wi)));
            }
            // The ideal parts (mirror, refraction) are the recursion's: only the lobes here.
            const vec2 u = stratified_sample(k, n, rng.next_2d());
            const BsdfSample b = sample_bsdf(bsdf, frame.ns, wo, frame.front, u, rng.next_float());
            if (b.valid() && !b.delta && reaches(b.wi))
                sum += b.weight * env.radiance(b.wi) *
                       power_heuristic(b.pdf, env.pdf(b.wi, EnvironmentDensity::Compensated));
        }
        return sum / static_cast<float>(n);
    }

    const RtScene& rt_;
    const Scene& scene_;
    bool want_visibility_;
};

/// What every pixel of a window reads and writes.
struct WindowContext {
    const Scene& scene;
    const RtScene& rt;
    const CameraRays& camera;
    const RenderOptions& options;
    const AovTargets& targets;
    Image* cost_image;  // the bvh_cost AOV, when asked for
    const Crop& window;
    RenderResult& result;  // the window's pixels
};

/// Pixel (i, j) of the film: its samples traced and their mean written.
void render_pixel(const WindowContext& c, Tracer& tracer, int i, int j) {
    const int width = c.scene.film.width, height = c.scene.film.height, spp = c.scene.render.spp;
    const CameraRays& camera = c.camera;
    const AovTargets& targets = c.targets;
    uint64_t pixel = static_cast<uint64_t>(j) * width + i;
    Rng rng = pixel_rng(c.scene.render.seed, pixel);
    Rng aov_rng = pixel_rng(c.scene.render.seed ^ 0xa0a0a0a0ULL, pixel);
    tracer.aov_rng = &aov_rng;
    glm::dvec3 sum(0.0);
    AovSum aov_sum;
    Color cost(0.0f);
    for (int s = 0; s < spp; ++s) {
        vec2 offset = spp == 1 ? vec2(0.5f) : stratified_sample(s, spp, rng.next_2d());
        const float x = (static_cast<float>(i) + offset.x) / width;
        const float y = (static_cast<float>(j) + offset.y) / height;
        Ray ray = camera.thin_lens() ? camera.generate(x, y, rng.next_2d()) : camera.generate(x, y);
        if (c.cost_image) cost += c.rt.camera_ray_cost(ray);
        AovSample aov;
        PixelTrace* log = c.options.trace;
        std::optional<WhittedTraceLog> traced;
        if (log && log->at(i, j) && log->sample == s) {
            traced.emplace(*log, c.scene.material_names);
            tracer.observer = &*traced;
        }
        Color radiance = tracer.trace(ray, 0, 1.0f, rng, targets.any ? &aov : nullptr);
        // A sample that is not finite never reaches the pixel: it is
        // dropped (black) and counted.
        const bool finite = is_finite(radiance) && is_finite(aov.normal) && is_finite(aov.albedo) &&
                            std::isfinite(aov.depth);
        if (traced) record_total(*log, radiance, finite);
        tracer.observer = nullptr;
        if (!finite) {
            ++tracer.nonfinite;
            continue;
        }
        sum += glm::dvec3(radiance);
        if (targets.any) aov_sum.add(aov);
    }
    float inv = 1.0f / static_cast<float>(spp);
    const int x = i - c.window.x0, y = j - c.window.y0;
    c.result.color.at(x, y) = Color(sum / static_cast<double>(spp));
    if (targets.any) targets.write(x, y, aov_sum.mean(spp));
    if (c.cost_image) c.cost_image->at(x, y) = cost * inv;
}

}  // namespace

RenderResult WhittedRenderer::render(const Scene& scene, const RenderOptions& options) {
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    RtScene rt(scene, scene.render.accel, options.threads, options.accels);
    auto t1 = Clock::now();

    const int width = scene.film.width, height = scene.film.height;
    // The debug AOV: the camera rays' cost, cast again (the image does not change).
    const bool want_cost = wants_debug_aov(options, "bvh_cost");
    if (want_cost) rt.check_counts_cost();
    CameraRays camera(scene.camera, width, height);
    // The pixels rendered: a window's (the crop's, or each of options.windows), at their
    // places in the full film (result pixel (i - x0, j - y0)); a pixel's samples depend only
    // on its place, so a window is the full render's.
    RenderResult all =
        render_windows(film_window(scene, options), options, [&](const Crop& window) {
            const auto start = Clock::now();
            RenderResult result;
            // Looked up once: the tiles write through these concurrently.
            const AovTargets targets =
                prepare_result(result, options.aovs, window.width(), window.height());
            bool want_visibility = targets.want(Aov::Visibility) && !scene.lights.empty();
            if (want_cost) result.aovs["bvh_cost"] = Image(window.width(), window.height());
            Image* cost_image = want_cost ? &result.aovs["bvh_cost"] : nullptr;
            std::atomic<uint64_t> rays{0}, nonfinite{0};
            Progress progress("whitted", static_cast<int64_t>(window.width()) * window.height(),
                              options.progress);
            const WindowContext context{scene,   rt,         camera, options,
                                        targets, cost_image, window, result};

            parallel_tiles(
                window.width(), window.height(), options.threads,
                [&](const Tile& tile) {
                    Tracer tracer(rt, want_visibility);
                    for (int j = window.y0 + tile.y0; j < window.y0 + tile.y1; ++j) {
                        for (int i = window.x0 + tile.x0; i < window.x0 + tile.x1; ++i) {
                            render_pixel(context, tracer, i, j);
                        }
                    }
                    rays += tracer.rays;
                    nonfinite += tracer.nonfinite;
                },
                [&](int pixels) { progress.advance(pixels); });
            progress.finish();
            result.stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
            result.stats.rays = rays.load();
            result.stats.nonfinite = nonfinite.load();
            return result;
        });
    all.stats.setup_seconds = std::chrono::duration<double>(t1 - t0).count();
    return all;
}

}  // namespace svetlo
