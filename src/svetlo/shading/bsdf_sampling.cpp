// Sampling of every BSDF (bsdf.h): the lobes, their pdfs, and the choice between them.
// Sources: pbrt-v4 chapter 9 (Pharr, Jakob, Humphreys 2023); Lafortune and Willems 1994 for
// the Phong lobes; Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 2018.
#include "svetlo/core/sampling.h"
#include "svetlo/shading/bsdf.h"

namespace svetlo {

namespace {

/// Probabilities of the lobes of a material: diffuse, glossy, delta reflection, delta
/// transmission, in proportion to their weights' luminance.
struct LobeChoice {
    float diffuse = 0.0f, glossy = 0.0f, reflect = 0.0f, transmit = 0.0f;
    float coat = 0.0f;  // Cook-Torrance's clear coat (a second GGX lobe)
};

LobeChoice lobe_choice(const Bsdf& b, float cos_o) {
    LobeChoice c;
    switch (b.model) {
        case Bsdf::Model::Lambert:
        case Bsdf::Model::OrenNayar:
        case Bsdf::Model::Emissive:
            c.diffuse = 1.0f;
            return c;
        case Bsdf::Model::Phong:
        case Bsdf::Model::BlinnPhong:
            c.diffuse = luminance(b.diffuse);
            c.glossy = luminance(b.specular);
            c.reflect = luminance(b.reflect);
            c.transmit = luminance(b.transmit);
            break;
        case Bsdf::Model::CookTorrance: {
            // The specular share at this angle (Schlick's Fresnel), against the diffuse.
            Color f = fresnel_schlick(b.specular, cos_o);
            const float under = under_coat(b, cos_o);
            c.glossy = luminance(f) * under;
            c.diffuse = luminance((Color(1.0f) - f) * b.diffuse) * under;
            c.transmit = luminance(transmitted_weight(b, cos_o));
            c.coat = b.coat * coat_fresnel(cos_o);
            break;
        }
        case Bsdf::Model::Mirror:
            c.reflect = 1.0f;
            return c;
        case Bsdf::Model::Dielectric:
            c.reflect = 1.0f;  // split by Fresnel in sample_bsdf
            return c;
    }
    float total = c.diffuse + c.glossy + c.reflect + c.transmit + c.coat;
    if (!(total > 0.0f)) return LobeChoice{};
    c.diffuse /= total;
    c.glossy /= total;
    c.reflect /= total;
    c.transmit /= total;
    c.coat /= total;
    return c;
}

/// A direction about +z with pdf (n+1)/(2 pi) cos^n (the Phong lobe's shape).
vec3 sample_power_cosine(vec2 u, float n) {
    float cos_t = std::pow(u.x, 1.0f / (n + 1.0f));
    float sin_t = safe_sqrt(1.0f - cos_t * cos_t);
    float phi = 2.0f * kPi * u.y;
    return vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
}

float power_cosine_pdf(float cos_t, float n) {
    return cos_t <= 0.0f ? 0.0f : (n + 1.0f) / (2.0f * kPi) * std::pow(cos_t, n);
}

/// GGX: the distribution D(h) and Smith's G1 for a direction with cosine `c` to the normal.
float ggx_d(float cos_h, float alpha) {
    float a2 = alpha * alpha;
    return a2 / (kPi * square(cos_h * cos_h * (a2 - 1.0f) + 1.0f));
}
float ggx_g1(float c, float alpha) {
    float a2 = alpha * alpha;
    return 2.0f * c / (c + std::sqrt(a2 + (1.0f - a2) * c * c));
}

/// A visible normal of GGX for wo (local space, wo.z > 0): Heitz 2018, listing 1.
vec3 sample_ggx_visible(vec3 wo, float alpha, vec2 u) {
    vec3 vh = glm::normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    float len2 = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = len2 > 0.0f ? vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : vec3(1.0f, 0.0f, 0.0f);
    vec3 t2 = glm::cross(vh, t1);
    float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
    float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + safe_sqrt(1.0f - p1 * p1 - p2 * p2) * vh;
    return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

/// pdf per steradian of GGX's visible normals reflecting wo into wi (local space):
/// G1(wo) D(h) / (4 cos_o).
float ggx_reflection_pdf(vec3 wo, vec3 wi, float alpha) {
    vec3 h = glm::normalize(wo + wi);
    if (h.z <= 0.0f || glm::dot(wo, h) <= 0.0f) return 0.0f;
    return ggx_g1(wo.z, alpha) * ggx_d(h.z, alpha) / (4.0f * wo.z);
}

/// pdf per steradian of the glossy lobe drawing wi (local space, both above the surface).
float glossy_pdf(const Bsdf& b, vec3 wo, vec3 wi) {
    switch (b.model) {
        case Bsdf::Model::Phong:  // about the mirror direction of wo
            return power_cosine_pdf(glm::dot(vec3(-wo.x, -wo.y, wo.z), wi), b.shininess);
        case Bsdf::Model::BlinnPhong: {  // the half vector, then d(omega_h)/d(omega_i) = 1/(4 wo.h)
            vec3 h = glm::normalize(wo + wi);
            float oh = glm::dot(wo, h);
            return oh <= 0.0f ? 0.0f : power_cosine_pdf(h.z, b.shininess) / (4.0f * oh);
        }
        case Bsdf::Model::CookTorrance:
            return ggx_reflection_pdf(wo, wi, b.alpha);
        default:
            return 0.0f;
    }
}

/// The non-delta pdf in local space.
float local_pdf(const Bsdf& b, const LobeChoice& c, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float pdf = c.diffuse * wi.z * kInvPi;
    if (c.coat > 0.0f) pdf += c.coat * ggx_reflection_pdf(wo, wi, b.coat_alpha);
    return c.glossy > 0.0f ? pdf + c.glossy * glossy_pdf(b, wo, wi) : pdf;
}

/// Lambert's BRDF (and an emitter's albedo) are sampled by the cosine alone.
bool cosine_only(const Bsdf& b) {
    return b.model == Bsdf::Model::Lambert || b.model == Bsdf::Model::Emissive;
}

}  // namespace

float pdf_bsdf(const Bsdf& b, vec3 n, vec3 wo, vec3 wi) {
    if (cosine_only(b))
        return glm::dot(n, wo) > 0.0f ? std::max(0.0f, glm::dot(n, wi)) * kInvPi : 0.0f;
    Frame frame = Frame::from_normal(n);
    vec3 lo = frame.to_local(wo);
    return local_pdf(b, lobe_choice(b, lo.z), lo, frame.to_local(wi));
}

BsdfSample sample_bsdf(const Bsdf& b, vec3 n, vec3 wo, bool front, vec2 u, float u_lobe) {
    BsdfSample s;
    if (glm::dot(n, wo) <= 0.0f) return s;
    Frame frame = Frame::from_normal(n);
    if (cosine_only(b)) {  // f = albedo / pi, pdf = cos / pi: the weight is the albedo
        vec3 li = sample_cosine_hemisphere(u);
        if (!(li.z > 0.0f)) return s;
        s.wi = frame.to_world(li);
        s.pdf = li.z * kInvPi;
        s.f = b.diffuse * kInvPi;
        s.weight = b.diffuse;
        return s;
    }
    vec3 lo = frame.to_local(wo);
    if (lo.z <= 0.0f) return s;
    LobeChoice c = lobe_choice(b, lo.z);
    auto delta = [&](vec3 wi, Color weight, float probability) {
        s.wi = wi;
        s.delta = true;
        s.pdf = probability;
        s.weight = weight / probability;
        return s;
    };
    if (b.model == Bsdf::Model::Dielectric) {
        // Entering from the front; eta = n_transmitted / n_incident. Radiance is not scaled
        // by 1/eta^2 across the interface, as in the Whitted engine.
        float eta = front ? b.ior : 1.0f / b.ior;
        float fr = fresnel_dielectric(lo.z, eta);  // 1 under total internal reflection
        vec3 wt;
        if (u_lobe >= fr && refract(wo, n, eta, wt)) return delta(wt, Color(1.0f - fr), 1.0f - fr);
        return delta(reflect(wo, n), Color(fr), fr);
    }
    // The lobes in the order diffuse, glossy, delta reflection, delta transmission, coat.
    float x = u_lobe;
    if (x < c.reflect + c.diffuse + c.glossy && x >= c.diffuse + c.glossy)
        return delta(reflect(wo, n), b.reflect, c.reflect);
    const float before_coat = c.diffuse + c.glossy + c.reflect + c.transmit;
    if (x >= c.diffuse + c.glossy + c.reflect && x < before_coat && c.transmit > 0.0f) {
        float eta = front ? b.ior : 1.0f / b.ior;
        vec3 wt;
        // Under total internal reflection the transmitted part reflects (as in Whitted).
        if (!refract(wo, n, eta, wt)) wt = reflect(wo, n);
        const bool fresnel = b.model == Bsdf::Model::CookTorrance;
        return delta(wt, fresnel ? transmitted_weight(b, lo.z) : b.transmit, c.transmit);
    }
    vec3 li;
    if (x < c.diffuse) {
        li = sample_cosine_hemisphere(u);
    } else if (x >= before_coat && c.coat > 0.0f) {
        li = glm::reflect(-lo, sample_ggx_visible(lo, b.coat_alpha, u));
    } else if (c.glossy > 0.0f) {
        if (b.model == Bsdf::Model::CookTorrance) {
            li = glm::reflect(-lo, sample_ggx_visible(lo, b.alpha, u));
        } else if (b.model == Bsdf::Model::BlinnPhong) {
            li = glm::reflect(-lo, sample_power_cosine(u, b.shininess));
        } else {  // Phong: the lobe about the mirror direction
            li = Frame::from_normal(vec3(-lo.x, -lo.y, lo.z))
                     .to_world(sample_power_cosine(u, b.shininess));
        }
    } else {
        return s;  // nothing to sample: a black material
    }
    if (li.z <= 0.0f) return s;  // below the surface: f = 0
    s.wi = frame.to_world(li);
    s.pdf = local_pdf(b, c, lo, li);
    if (!(s.pdf > 0.0f)) return BsdfSample{};
    s.f = eval_bsdf(b, n, wo, s.wi);
    s.weight = s.f * (std::abs(glm::dot(n, s.wi)) / s.pdf);
    return s;
}

}  // namespace svetlo
