#include "svetlo/pt/caustic_photons.h"

#include <algorithm>
#include <atomic>

#include "svetlo/core/parallel.h"
#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/pt/light_selection.h"
#include "svetlo/shading/lights.h"

namespace svetlo {

namespace {

/// More targets than this are aimed at as one (the pdf of the aim is a sum over them).
constexpr size_t kMaxTargets = 64;
/// Photons per task: the split does not depend on the thread count, nor does the map.
constexpr uint64_t kPhotonsPerTask = 4096;
/// A photon counts for a point whose surface normal is within about 25 degrees of its own.
constexpr float kNormalAgreement = 0.9f;
/// A pass keeps at most this many photons per photon emitted (a photon leaves one where it
/// lands on each surface with a non-delta part that it meets through delta bounces), so that
/// its memory is bounded (scene_loader.h, kMaxPhotons); the rest of a task's are dropped.
constexpr size_t kStoredPerEmitted = 4;

/// The grid cell of p for cells of side `cell`, clamped so that the conversion to int is
/// defined for any radius and position.
glm::ivec3 cell_of(vec3 p, float cell) {
    vec3 c = glm::clamp(glm::floor(p / cell), vec3(-1073741824.0f), vec3(1073741824.0f));
    return glm::ivec3(c);
}

/// True when the material has an ideal mirror or refraction part.
bool is_delta(const Material& m, const std::vector<TextureImage>& textures) {
    Bsdf b = make_bsdf(m, vec2(0.5f), textures);
    return b.model == Bsdf::Model::Mirror || b.model == Bsdf::Model::Dielectric ||
           !is_black(b.reflect) || !is_black(b.transmit);
}

/// 1 - cos of the half-angle of the cone from a point at distance d to a sphere of radius r.
float cone_one_minus_cos(float r, float d) {
    float s2 = (r * r) / (d * d);
    return s2 / (1.0f + std::sqrt(std::max(0.0f, 1.0f - s2)));
}

}  // namespace

CausticPhotons::CausticPhotons(const RtScene& rt, const WavelengthWeights& wavelengths,
                               float diameter)
    : rt_(rt), wavelengths_(wavelengths), diameter_(diameter) {
    const Scene& scene = rt.scene();
    const RenderSettings& settings = scene.render;
    if (settings.caustics == CausticMode::None) return;
    covers_area_lights_ = settings.caustics == CausticMode::Photons;

    // Targets: the bounds of each object's delta primitives, as a sphere.
    const Geometry& g = rt.geometry();
    std::vector<char> delta_material;
    for (const Material& m : rt.materials()) delta_material.push_back(is_delta(m, scene.textures));
    Bounds3 all;
    for (const PrimitiveRange& r : rt.object_ranges()) {
        Bounds3 b;
        for (uint32_t id = r.first; id < r.end; ++id) {
            if (delta_material[g.material(id)]) b.extend(g.primitive_bounds(id));
        }
        if (b.empty() || !std::isfinite(b.min.x + b.min.y + b.min.z + b.max.x + b.max.y + b.max.z))
            continue;  // none, or an infinite mirror plane: nothing to aim at
        targets_.push_back({b.center(), 0.5f * glm::length(b.extent()) * 1.0001f + 1e-6f});
        all.extend(b);
    }
    if (targets_.size() > kMaxTargets)
        targets_ = {{all.center(), 0.5f * glm::length(all.extent()) * 1.0001f + 1e-6f}};
    if (targets_.empty()) return;

    // Lights, chosen in proportion to the flux they send toward the targets (roughly: any
    // positive choice is unbiased, since each photon is divided by its probability).
    const auto& sources = rt.lights().sources();
    float total = 0.0f;
    for (size_t k = 0; k < sources.size(); ++k) {
        const LightSet::Source& s = sources[k];
        float f = 0.0f;
        bool spot_cone = false;
        if (!s.delta) {
            if (covers_area_lights_)
                f = static_cast<float>(light_power(rt.lights(), s, scene, 0.0f));
        } else {
            // The intensity a delta light sends into the targets' cones (or its spot's cone).
            const Light& light = scene.lights[static_cast<size_t>(s.light_index)];
            if (const auto* d = std::get_if<DirectionalLight>(&light)) {
                for (const Target& t : targets_)
                    f += luminance(d->irradiance) * kPi * t.radius * t.radius;
            } else {
                const auto* point = std::get_if<PointLight>(&light);
                const auto* spot = std::get_if<SpotLight>(&light);
                const vec3 x = point ? point->position : spot->position;
                float solid = 0.0f;
                for (const Target& t : targets_) {
                    float dist = glm::length(t.center - x);
                    solid += dist <= t.radius ? 4.0f * kPi
                                              : 2.0f * kPi * cone_one_minus_cos(t.radius, dist);
                }
                solid = std::min(solid, 4.0f * kPi);
                if (spot) {
                    float cone = 2.0f * kPi * (1.0f - std::cos(radians(spot->outer_deg)));
                    spot_cone = cone < solid;
                    solid = std::min(solid, cone);
                }
                f = luminance(point ? point->intensity : spot->intensity) * solid;
            }
        }
        if (f > 0.0f && std::isfinite(f)) {
            emitters_.push_back({static_cast<int>(k), f, spot_cone});
            total += f;
        }
    }
    for (Emitter& e : emitters_) e.probability /= total;  // the flux, until here
}

vec3 CausticPhotons::in_cone(vec3 axis, float one_minus_cos, vec2 u) {
    // cos theta uniform on [1 - one_minus_cos, 1].
    float omc = u.x * one_minus_cos;
    float sin_t = safe_sqrt(omc * (2.0f - omc));
    float phi = 2.0f * kPi * u.y;
    return Frame::from_normal(axis).to_world(
        vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), 1.0f - omc));
}

vec3 CausticPhotons::aim(vec3 x, vec2 u, float u_pick) const {
    size_t k = std::min(static_cast<size_t>(u_pick * static_cast<float>(targets_.size())),
                        targets_.size() - 1);
    const Target& t = targets_[k];
    vec3 d = t.center - x;
    float dist = glm::length(d);
    if (dist <= t.radius) return sample_uniform_sphere(u);
    // Uniform in the cone: cos theta uniform on [cos_max, 1].
    float one_minus_cos = u.x * cone_one_minus_cos(t.radius, dist);
    float cos_t = 1.0f - one_minus_cos;
    float sin_t = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
    float phi = 2.0f * kPi * u.y;
    return Frame::from_normal(d / dist).to_world(
        vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
}

float CausticPhotons::aim_pdf(vec3 x, vec3 w) const {
    float pdf = 0.0f;
    for (const Target& t : targets_) {
        vec3 d = t.center - x;
        float dist = glm::length(d);
        if (dist <= t.radius) {
            pdf += 1.0f / (4.0f * kPi);
            continue;
        }
        float omc = cone_one_minus_cos(t.radius, dist);
        if (1.0f - glm::dot(w, d / dist) <= omc) pdf += 1.0f / (2.0f * kPi * omc);
    }
    return pdf / static_cast<float>(targets_.size());
}

Ray CausticPhotons::punctual_photon(const Light& light, bool spot_cone, vec2 u1, float u_pick,
                                    Color& power) const {
    if (const auto* d = std::get_if<DirectionalLight>(&light)) {
        // From a disc across a target's sphere, far up the light's direction.
        size_t k = std::min(static_cast<size_t>(u_pick * static_cast<float>(targets_.size())),
                            targets_.size() - 1);
        Frame f = Frame::from_normal(d->direction);
        vec2 disc = targets_[k].radius * sample_disk_concentric(u1);
        vec3 on_plane = targets_[k].center + disc.x * f.t + disc.y * f.b;
        float pdf_area = 0.0f;  // of the mixture of the targets' discs, per m^2
        for (const Target& t : targets_) {
            vec3 off = on_plane - t.center;
            off -= glm::dot(off, d->direction) * d->direction;
            if (glm::dot(off, off) <= t.radius * t.radius)
                pdf_area += 1.0f / (kPi * t.radius * t.radius);
        }
        pdf_area /= static_cast<float>(targets_.size());
        power = d->irradiance / pdf_area;
        return Ray{on_plane - d->direction * (2.0f * diameter_), d->direction, kInfinity};
    }
    // A point or spot light.
    vec3 x = std::holds_alternative<PointLight>(light) ? std::get<PointLight>(light).position
                                                       : std::get<SpotLight>(light).position;
    vec3 w;
    float pdf;
    if (spot_cone) {
        const auto& spot = std::get<SpotLight>(light);
        float omc = 1.0f - std::cos(radians(spot.outer_deg));
        w = in_cone(spot.direction, omc, u1);
        pdf = 1.0f / (2.0f * kPi * omc);
    } else {
        w = aim(x, u1, u_pick);
        pdf = aim_pdf(x, w);
    }
    // I(w): the irradiance at unit distance along w.
    Color intensity = sample_punctual(light, x + w).irradiance;
    power = intensity / pdf;
    return Ray{x, w, kInfinity};
}

void CausticPhotons::trace_photon(uint64_t index, int pass, int count, std::vector<Photon>& out,
                                  size_t cap, uint64_t& rays) const {
    const Scene& scene = rt_.scene();
    const LightSet& lights = rt_.lights();
    Rng rng(mix64(mix64(scene.render.seed) + 0x70686f746f6eULL + static_cast<uint64_t>(pass)),
            mix64(index));
    // The light, by its probability.
    float u_light = rng.next_float();
    size_t e = 0;
    while (e + 1 < emitters_.size() && u_light >= emitters_[e].probability) {
        u_light -= emitters_[e].probability;
        ++e;
    }
    const LightSet::Source& source = lights.sources()[static_cast<size_t>(emitters_[e].source)];
    const float scale = 1.0f / (emitters_[e].probability * static_cast<float>(count));
    vec2 u1 = rng.next_2d(), u2 = rng.next_2d();
    float u_pick = rng.next_float();

    Ray ray;
    Color power(0.0f);
    if (source.delta) {
        ray = punctual_photon(scene.lights[static_cast<size_t>(source.light_index)],
                              emitters_[e].spot_cone, u1, u_pick, power);
    } else {
        AreaPoint a = lights.sample_area(source, u1, u_pick);
        vec3 w = aim(a.surface.p, u2, rng.next_float());
        float cos_light = glm::dot(a.surface.n, w);
        if (cos_light <= 0.0f) return;  // behind the light: this photon carries nothing
        ray = Ray{offset_ray_origin(a.surface.p, a.surface.n, w), w, kInfinity};
        power = a.radiance * (cos_light / (a.pdf_area * aim_pdf(a.surface.p, w)));
    }
    power *= scale;
    if (!is_finite(power) || is_black(power)) return;

    float lambda = 0.0f;
    int delta_bounces = 0;
    for (int bounce = 0; bounce <= scene.render.max_depth; ++bounce) {
        ++rays;
        Hit hit;
        if (!rt_.intersect(ray, hit)) return;
        SurfaceHit sh = rt_.surface(ray, hit);
        Bsdf bsdf = rt_.bsdf(sh.material, sh.varyings());
        const vec3 wo = -glm::normalize(ray.d);
        const ShadingFrame frame = make_shading_frame(sh.ng, sh.ns, wo);
        bsdf.coat_normal = seen_coat_normal(sh.coat_ns, frame, wo);
        if (bsdf.has_lobes() && delta_bounces > 0 && out.size() < cap)
            out.push_back({sh.p, wo, frame.ng, power});
        if (bsdf.model == Bsdf::Model::Dielectric && bsdf.abbe > 0.0f) {
            if (lambda == 0.0f) {
                lambda = WavelengthWeights::lambda_of(rng.next_float());
                power *= wavelengths_.weight(lambda);
            }
            bsdf.ior = cauchy_ior(bsdf.ior, bsdf.abbe, lambda);
        }
        vec2 u = rng.next_2d();
        BsdfSample bs = sample_bsdf(bsdf, frame.ns, wo, frame.front, u, rng.next_float());
        if (!bs.valid() || !bs.delta) return;  // only delta bounces make caustics
        power *= bs.weight;
        if (is_black(power)) return;
        ++delta_bounces;
        ray = Ray{offset_ray_origin(sh.p, frame.ng, bs.wi), bs.wi, kInfinity};
    }
}

size_t CausticPhotons::bucket(glm::ivec3 c) const {
    auto h = static_cast<uint64_t>(static_cast<uint32_t>(c.x)) * 73856093ULL ^
             static_cast<uint64_t>(static_cast<uint32_t>(c.y)) * 19349663ULL ^
             static_cast<uint64_t>(static_cast<uint32_t>(c.z)) * 83492791ULL;
    return static_cast<size_t>(mix64(h) & (bucket_start_.size() - 2));
}

void CausticPhotons::shrink_radius(int pass) {
    const PhotonSettings& settings = rt_.scene().render.photons;
    // The pass's radius: r_0 from the settings, then Knaus and Zwicker's shrinking, one step
    // per pass (passes are built in order).
    if (pass == 0) {
        radius2_ = settings.radius > 0.0f ? double(settings.radius) * settings.radius
                                          : std::pow(double(diameter_) / 300.0, 2.0);
    } else {
        radius2_ *= (pass + double(settings.alpha)) / (pass + 1);
    }
    radius_ = static_cast<float>(std::sqrt(radius2_));
    cell_ = 2.0f * radius_;
}

void CausticPhotons::build(int pass, int threads) {
    const PhotonSettings& settings = rt_.scene().render.photons;
    shrink_radius(pass);

    const auto count = static_cast<uint64_t>(settings.count);
    const size_t tasks = static_cast<size_t>((count + kPhotonsPerTask - 1) / kPhotonsPerTask);
    std::vector<std::vector<Photon>> found(tasks);
    std::atomic<uint64_t> rays{0};
    parallel_indices(tasks, threads, [&](size_t t) {
        uint64_t local = 0;
        uint64_t end = std::min(count, (t + 1) * kPhotonsPerTask);
        const size_t cap = kStoredPerEmitted * (end - t * kPhotonsPerTask);
        for (uint64_t i = t * kPhotonsPerTask; i < end; ++i)
            trace_photon(i, pass, settings.count, found[t], cap, local);
        rays += local;
    });
    rays_ += rays.load();

    // Counting sort, in the tasks' order, into the buckets of a hashed grid of cells of side
    // 2r: a query's sphere touches at most 2 x 2 x 2 cells.
    size_t total = 0;
    for (const auto& f : found) total += f.size();
    size_t buckets = 1;
    while (buckets < std::max<size_t>(total, 1)) buckets <<= 1;
    bucket_start_.assign(buckets + 1, 0);
    std::vector<uint32_t> key;
    key.reserve(total);
    for (const auto& f : found) {
        for (const Photon& ph : f) {
            key.push_back(static_cast<uint32_t>(bucket(cell_of(ph.p, cell_))));
            ++bucket_start_[key.back() + 1];
        }
    }
    for (size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
    photons_.resize(total);
    std::vector<uint32_t> next(bucket_start_.begin(), bucket_start_.end() - 1);
    size_t k = 0;
    for (auto& f : found) {
        for (const Photon& ph : f) photons_[next[key[k++]]++] = ph;
        std::vector<Photon>().swap(f);  // freed as it goes: at most one copy and a part
    }
}

Color CausticPhotons::radiance(vec3 p, const ShadingFrame& frame, vec3 wo, const Bsdf& bsdf) const {
    const float r2 = radius_ * radius_;
    if (photons_.empty() || !(r2 > 0.0f)) return Color(0.0f);
    glm::ivec3 lo = cell_of(p - vec3(radius_), cell_);
    size_t seen[8];
    int n_seen = 0;
    Color sum(0.0f);
    for (int c = 0; c < 8; ++c) {
        size_t b = bucket(lo + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2));
        if (std::find(seen, seen + n_seen, b) != seen + n_seen) continue;  // hash collision
        seen[n_seen++] = b;
        for (uint32_t i = bucket_start_[b]; i < bucket_start_[b + 1]; ++i) {
            const Photon& ph = photons_[i];
            vec3 d = ph.p - p;
            if (glm::dot(d, d) > r2 || glm::dot(ph.n, frame.ng) < kNormalAgreement) continue;
            sum += eval_bsdf(bsdf, frame.ns, wo, ph.wi) * ph.power;
        }
    }
    return sum / (kPi * r2);
}

}  // namespace svetlo
