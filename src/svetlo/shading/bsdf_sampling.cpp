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
            Color f = specular_fresnel(b, cos_o);
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

/// GGX: Smith's G1 for a direction with cosine `c` to the normal (D is ggx_d, bsdf.h).
float ggx_g1(float c, float alpha) {
    float a2 = alpha * alpha;
    return 2.0f * c / (c + std::sqrt(a2 + (1.0f - a2) * c * c));
}

/// Smith's Lambda of GGX for a direction at cosine c to the normal, on either side:
/// (sqrt(1 + alpha^2 tan^2) - 1) / 2.
float ggx_lambda(float c, float alpha) {
    c = std::abs(c);
    float a2 = alpha * alpha;
    return 0.5f * (std::sqrt(a2 + (1.0f - a2) * c * c) / c - 1.0f);
}

/// The height-correlated masking-shadowing of GGX for two directions (pbrt-v4, 9.6.3).
float ggx_g2(float cos_o, float cos_i, float alpha) {
    return 1.0f / (1.0f + ggx_lambda(cos_o, alpha) + ggx_lambda(cos_i, alpha));
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
    return ggx_g1(wo.z, alpha) * ggx_d(h.z, h.x * h.x + h.y * h.y, alpha) / (4.0f * wo.z);
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

/// The clear coat's frame within the local frame of n, where it has a normal of its own.
struct CoatFrame {
    bool own = false;
    Frame frame{vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1)};
};

CoatFrame coat_frame(const Bsdf& b, const Frame& frame) {
    CoatFrame c;
    if (has_coat_normal(b)) {
        c.own = true;
        c.frame = Frame::from_normal(glm::normalize(frame.to_local(b.coat_normal)));
    }
    return c;
}

/// The coat lobe's pdf (local space): GGX's visible normals about the coat's normal.
float coat_pdf(const Bsdf& b, const CoatFrame& cf, vec3 wo, vec3 wi) {
    if (!cf.own) return ggx_reflection_pdf(wo, wi, b.coat_alpha);
    const vec3 oc = cf.frame.to_local(wo);
    return oc.z > 0.0f ? ggx_reflection_pdf(oc, cf.frame.to_local(wi), b.coat_alpha) : 0.0f;
}

/// The non-delta pdf in local space.
float local_pdf(const Bsdf& b, const LobeChoice& c, const CoatFrame& cf, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float pdf = c.diffuse * wi.z * kInvPi;
    if (c.coat > 0.0f) pdf += c.coat * coat_pdf(b, cf, wo, wi);
    return c.glossy > 0.0f ? pdf + c.glossy * glossy_pdf(b, wo, wi) : pdf;
}

/// How the rough transmitted part carries wo to wi (local space, wo.z > 0): through the
/// microfacet normal m, refracted (wi below) or totally reflected (wi above); `valid` is
/// false where no microfacet does.
struct TransmittedPath {
    vec3 m{0.0f, 0.0f, 1.0f};
    bool refracted = false, valid = false;
};

/// eta = n_t / n_i, the index of wi's side over wo's.
TransmittedPath transmitted_path(vec3 lo, vec3 li, float eta) {
    TransmittedPath p;
    p.refracted = li.z < 0.0f;
    if (p.refracted) {
        // The generalised half vector of refraction (Walter et al. 2007, eq. 16).
        vec3 m = eta * li + lo;
        if (glm::dot(m, m) == 0.0f) return p;
        p.m = glm::normalize(m) * (m.z < 0.0f ? -1.0f : 1.0f);
        p.valid = glm::dot(lo, p.m) > 0.0f && glm::dot(li, p.m) < 0.0f;
    } else {
        vec3 m = lo + li;
        if (li.z <= 0.0f || glm::dot(m, m) == 0.0f) return p;
        p.m = glm::normalize(m);
        const float c = glm::dot(lo, p.m);
        p.valid = c > 0.0f && (1.0f - c * c) >= eta * eta;  // total internal reflection at m
    }
    return p;
}

/// The rough transmitted part's f and pdf (bsdf.h: eval_transmitted, pdf_transmitted) in
/// local space, the lobe's probability `chosen` included in the pdf.
void transmitted_local(const Bsdf& b, vec3 lo, vec3 li, float eta, float chosen, Color& f,
                       float& pdf) {
    f = Color(0.0f);
    pdf = 0.0f;
    const TransmittedPath p = transmitted_path(lo, li, eta);
    if (!p.valid || lo.z <= 0.0f || li.z == 0.0f) return;
    const float om = glm::dot(lo, p.m), im = std::abs(glm::dot(li, p.m));
    const float d = ggx_d(p.m.z, p.m.x * p.m.x + p.m.y * p.m.y, b.alpha),
                g = ggx_g2(lo.z, li.z, b.alpha);
    const Color t = b.transmit * (Color(1.0f) - specular_fresnel(b, om)) * under_coat(b, lo.z);
    const float visible = ggx_g1(lo.z, b.alpha) * d * om / lo.z;  // visible normals' density
    if (p.refracted) {
        const float denom = square(glm::dot(li, p.m) + om / eta);
        f = t * (d * g * im * om / (std::abs(li.z) * lo.z * denom));
        pdf = chosen * visible * im / denom;  // d(omega_m) / d(omega_i) = |i.m| / denom
    } else {
        f = t * (d * g / (4.0f * li.z * lo.z));
        pdf = chosen * visible / (4.0f * om);
    }
}

/// Lambert's BRDF (and an emitter's albedo) are sampled by the cosine alone.
bool cosine_only(const Bsdf& b) {
    return b.model == Bsdf::Model::Lambert || b.model == Bsdf::Model::Emissive;
}

/// A direction through the rough transmitted part: a visible microfacet normal of GGX, and wo
/// refracted through it (reflected where it reflects totally). Its weight is
/// f |cos_i| / pdf = T G2 / G1 over the lobe's probability (Heitz 2018, section 2).
BsdfSample sample_rough_transmission(const Bsdf& b, const Frame& frame, vec3 lo, float eta,
                                     float chosen, vec2 u) {
    BsdfSample s;
    const vec3 m = sample_ggx_visible(lo, b.alpha, u);
    vec3 li;
    const bool refracted = refract(lo, m, eta, li);
    if (!refracted) li = glm::reflect(-lo, m);
    if (refracted ? li.z >= 0.0f : li.z <= 0.0f) return s;  // a microfacet sends it back: lost
    const float om = glm::dot(lo, m);
    if (!(om > 0.0f)) return s;
    const Color t = b.transmit * (Color(1.0f) - specular_fresnel(b, om)) * under_coat(b, lo.z);
    s.wi = frame.to_world(li);
    s.weight = t * (ggx_g2(lo.z, li.z, b.alpha) / (ggx_g1(lo.z, b.alpha) * chosen));
    transmitted_local(b, lo, li, eta, chosen, s.f, s.pdf);
    s.delta = true;  // light sampling never draws it: what it reaches counts in full
    if (!(s.pdf > 0.0f)) return BsdfSample{};
    return s;
}

}  // namespace

Color eval_transmitted(const Bsdf& b, vec3 n, vec3 wo, vec3 wi, bool front) {
    Color f(0.0f);
    float pdf;
    if (!rough_transmission(b) || glm::dot(n, wo) <= 0.0f) return f;
    Frame frame = Frame::from_normal(n);
    vec3 lo = frame.to_local(wo);
    transmitted_local(b, lo, frame.to_local(wi), front ? b.ior : 1.0f / b.ior, 1.0f, f, pdf);
    return f;
}

float pdf_transmitted(const Bsdf& b, vec3 n, vec3 wo, vec3 wi, bool front) {
    Color f;
    float pdf = 0.0f;
    if (!rough_transmission(b) || glm::dot(n, wo) <= 0.0f) return pdf;
    Frame frame = Frame::from_normal(n);
    vec3 lo = frame.to_local(wo);
    const float chosen = lobe_choice(b, lo.z).transmit;
    transmitted_local(b, lo, frame.to_local(wi), front ? b.ior : 1.0f / b.ior, chosen, f, pdf);
    return pdf;
}

float pdf_bsdf(const Bsdf& b, vec3 n, vec3 wo, vec3 wi) {
    if (cosine_only(b))
        return glm::dot(n, wo) > 0.0f ? std::max(0.0f, glm::dot(n, wi)) * kInvPi : 0.0f;
    Frame frame = Frame::from_normal(n);
    vec3 lo = frame.to_local(wo);
    return local_pdf(b, lobe_choice(b, lo.z), coat_frame(b, frame), lo, frame.to_local(wi));
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
    const CoatFrame cf = coat_frame(b, frame);
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
        if (rough_transmission(b))
            return sample_rough_transmission(b, frame, lo, eta, c.transmit, u);
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
        if (!cf.own) {
            li = glm::reflect(-lo, sample_ggx_visible(lo, b.coat_alpha, u));
        } else {  // about the coat's own normal
            const vec3 oc = cf.frame.to_local(lo);
            if (oc.z <= 0.0f) return s;
            li = cf.frame.to_world(glm::reflect(-oc, sample_ggx_visible(oc, b.coat_alpha, u)));
        }
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
    s.pdf = local_pdf(b, c, cf, lo, li);
    if (!(s.pdf > 0.0f)) return BsdfSample{};
    s.f = eval_bsdf(b, n, wo, s.wi);
    s.weight = s.f * (std::abs(glm::dot(n, s.wi)) / s.pdf);
    return s;
}

}  // namespace svetlo
