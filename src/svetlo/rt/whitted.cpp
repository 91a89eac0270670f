#include "svetlo/rt/whitted.h"

#include <atomic>
#include <chrono>

#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"
#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/rt/camera.h"
#include "svetlo/rt/rt_scene.h"
#include "svetlo/rt/shadow_rays.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/direct_light.h"
#include "svetlo/shading/shading_frame.h"

namespace svetlo {

namespace {

/// Branches whose weight falls below this are not traced: Hall and Greenberg's adaptive
/// tree-depth control ("A Testbed for Realistic Image Synthesis", IEEE CG&A 1983). It drops
/// contributions under 1e-5 of the pixel's radiance scale.
constexpr float kMinBranchWeight = 1e-5f;

class Tracer {
public:
    Tracer(const RtScene& rt, bool want_visibility)
        : rt_(rt), scene_(rt.scene()), want_visibility_(want_visibility) {}

    uint64_t rays = 0;
    uint64_t nonfinite = 0;  // camera samples dropped for a radiance that is not finite
    Rng* aov_rng = nullptr;  // the visibility AOV's own stream, so AOVs never change the image

    Color trace(const Ray& ray, int depth, float weight, Rng& rng, AovSample* aov) {
        ++rays;
        Hit hit;
        if (!rt_.intersect(ray, hit)) return scene_.render.background;
        const Geometry& g = rt_.geometry();
        SurfaceHit sh = g.surface(ray, hit);
        Bsdf bsdf = rt_.bsdf(sh.material, sh.uv);
        vec3 wo = -glm::normalize(ray.d);
        const ShadingFrame frame = make_shading_frame(sh.ng, sh.ns, wo);
        const bool front = frame.front;
        const vec3 ng = frame.ng, ns = frame.ns;

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
        L += direct_light(rt_.lights(), bsdf, sh.p, frame, wo,
                          StratifiedLightSampling{rt_.lights(), rng, scene_.render.light_samples},
                          [&](size_t, const LightSample& s) {
                              return shadow_blocked(rt_, sh.p, ng, s, rays) ? 0.0f : 1.0f;
                          });
        if (depth >= scene_.render.max_depth) return L;

        auto follow = [&](Color scale, vec3 dir) {
            float w = weight * max_component(scale);
            if (w < kMinBranchWeight) return Color(0.0f);
            Ray next{offset_ray_origin(sh.p, ng, dir), dir, kInfinity};
            return scale * trace(next, depth + 1, w, rng, nullptr);
        };
        switch (bsdf.model) {
            case Bsdf::Model::Mirror:
                L += follow(bsdf.reflect, reflect(wo, ns));
                break;
            case Bsdf::Model::Dielectric: {
                // Entering when we hit the outside; eta = n_transmitted / n_incident.
                float eta = front ? bsdf.ior : 1.0f / bsdf.ior;
                float fr = fresnel_dielectric(glm::dot(ns, wo), eta);
                vec3 wt;
                if (fr < 1.0f && refract(wo, ns, eta, wt))
                    L += follow(Color(1.0f - fr), wt);
                else
                    fr = 1.0f;  // total internal reflection
                L += follow(Color(fr), reflect(wo, ns));
                break;
            }
            case Bsdf::Model::Phong:
            case Bsdf::Model::BlinnPhong: {
                if (!is_black(bsdf.reflect)) L += follow(bsdf.reflect, reflect(wo, ns));
                if (!is_black(bsdf.transmit)) {
                    float eta = front ? bsdf.ior : 1.0f / bsdf.ior;
                    vec3 wt;
                    // Under total internal reflection the transmitted part reflects.
                    if (!refract(wo, ns, eta, wt)) wt = reflect(wo, ns);
                    L += follow(bsdf.transmit, wt);
                }
                break;
            }
            default:
                break;
        }
        return L;
    }

private:
    const RtScene& rt_;
    const Scene& scene_;
    bool want_visibility_;
};

}  // namespace

RenderResult WhittedRenderer::render(const Scene& scene, const RenderOptions& options) {
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    RtScene rt(scene, scene.render.accel, options.threads);
    auto t1 = Clock::now();

    const int width = scene.film.width, height = scene.film.height, spp = scene.render.spp;
    // The pixels rendered: the crop's, at their places in the full film (result pixel (i - x0,
    // j - y0)); a pixel's samples depend only on its place, so a crop is the full render's.
    const Crop window = film_window(scene, options);
    RenderResult result;
    // Looked up once: the tiles write through these concurrently.
    const AovTargets targets =
        prepare_result(result, options.aovs, window.width(), window.height());
    bool want_visibility = targets.want[3] && !scene.lights.empty();
    CameraRays camera(scene.camera, width, height);
    std::atomic<uint64_t> rays{0}, nonfinite{0};
    Progress progress("whitted", static_cast<int64_t>(window.width()) * window.height(),
                      options.progress);

    parallel_tiles(
        window.width(), window.height(), options.threads,
        [&](const Tile& tile) {
            Tracer tracer(rt, want_visibility);
            for (int j = window.y0 + tile.y0; j < window.y0 + tile.y1; ++j) {
                for (int i = window.x0 + tile.x0; i < window.x0 + tile.x1; ++i) {
                    uint64_t pixel = static_cast<uint64_t>(j) * width + i;
                    Rng rng = pixel_rng(scene.render.seed, pixel);
                    Rng aov_rng = pixel_rng(scene.render.seed ^ 0xa0a0a0a0ULL, pixel);
                    tracer.aov_rng = &aov_rng;
                    glm::dvec3 sum(0.0);
                    AovSample aov_sum{0.0f, vec3(0.0f), Color(0.0f), 0.0f};
                    for (int s = 0; s < spp; ++s) {
                        vec2 offset = spp == 1
                                          ? vec2(0.5f)
                                          : stratified_sample(
                                                s, spp, vec2(rng.next_float(), rng.next_float()));
                        const float x = (static_cast<float>(i) + offset.x) / width;
                        const float y = (static_cast<float>(j) + offset.y) / height;
                        Ray ray = camera.thin_lens() ? camera.generate(x, y, rng.next_2d())
                                                     : camera.generate(x, y);
                        AovSample aov;
                        Color c = tracer.trace(ray, 0, 1.0f, rng, targets.any ? &aov : nullptr);
                        // A sample that is not finite never reaches the pixel: it is dropped
                        // (black) and counted.
                        if (!is_finite(c) || !is_finite(aov.normal) || !is_finite(aov.albedo) ||
                            !std::isfinite(aov.depth)) {
                            ++tracer.nonfinite;
                            continue;
                        }
                        sum += glm::dvec3(c);
                        if (targets.any) {
                            aov_sum.depth += aov.depth;
                            aov_sum.normal += aov.normal;
                            aov_sum.albedo += aov.albedo;
                            aov_sum.visibility += aov.visibility;
                        }
                    }
                    float inv = 1.0f / static_cast<float>(spp);
                    const int x = i - window.x0, y = j - window.y0;
                    result.color.at(x, y) = Color(sum / static_cast<double>(spp));
                    if (targets.want[0]) targets.image[0]->at(x, y) = Color(aov_sum.depth * inv);
                    if (targets.want[1]) targets.image[1]->at(x, y) = aov_sum.normal * inv;
                    if (targets.want[2]) targets.image[2]->at(x, y) = aov_sum.albedo * inv;
                    if (targets.want[3])
                        targets.image[3]->at(x, y) = Color(aov_sum.visibility * inv);
                }
            }
            rays += tracer.rays;
            nonfinite += tracer.nonfinite;
        },
        [&](int pixels) { progress.advance(pixels); });
    progress.finish();
    result.stats.setup_seconds = std::chrono::duration<double>(t1 - t0).count();
    result.stats.seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    result.stats.rays = rays.load();
    result.stats.nonfinite = nonfinite.load();
    return result;
}

}  // namespace svetlo
