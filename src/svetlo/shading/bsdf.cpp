#include "svetlo/shading/bsdf.h"

#include "svetlo/shading/texture.h"

namespace svetlo {

namespace {

struct BsdfMaker {
    const Varyings& at;
    const TextureLookup& lookup;

    Color c(const ColorSource& s) const { return eval_color(s, at, lookup); }

    Bsdf operator()(const LambertMaterial& m) const {
        Bsdf b;
        b.model = Bsdf::Model::Lambert;
        b.diffuse = b.ambient = c(m.albedo);
        return b;
    }
    Bsdf operator()(const PhongMaterial& m) const {
        Bsdf b;
        b.model = m.blinn ? Bsdf::Model::BlinnPhong : Bsdf::Model::Phong;
        b.ambient = c(m.ka);
        b.diffuse = c(m.kd);
        b.specular = c(m.ks);
        b.shininess = m.shininess *
                      (m.shininess_map.varies() ? c(m.shininess_map).r : m.shininess_map.value.r);
        b.reflect = c(m.reflect);
        b.transmit = c(m.transmit);
        b.ior = m.ior;
        // Nothing but the diffuse part: the Lambert BRDF, which the engines sample and
        // evaluate more cheaply.
        if (is_black(b.specular) && is_black(b.reflect) && is_black(b.transmit))
            b.model = Bsdf::Model::Lambert;
        return b;
    }
    Bsdf operator()(const OrenNayarMaterial& m) const {
        Bsdf b;
        b.model = Bsdf::Model::OrenNayar;
        b.diffuse = b.ambient = c(m.albedo);
        float s2 = square(radians(m.sigma_deg));
        b.on_a = 1.0f - 0.5f * s2 / (s2 + 0.33f);
        b.on_b = 0.45f * s2 / (s2 + 0.09f);
        return b;
    }
    Bsdf operator()(const CookTorranceMaterial& m) const {
        Bsdf b;
        b.model = Bsdf::Model::CookTorrance;
        Color base = c(m.base_color);
        const Color mr = c(m.metallic_roughness);  // glTF: G roughness, B metallic
        const float metallic = std::clamp(m.metallic * mr.b, 0.0f, 1.0f);
        const float roughness = std::clamp(m.roughness * mr.g, 0.0f, 1.0f);
        // KHR_materials_transmission: the transmitted share t of the dielectric's diffuse part.
        const float t = m.transmission.varies() || m.transmission.value.r != 0.0f
                            ? std::clamp(c(m.transmission).r, 0.0f, 1.0f)
                            : 0.0f;
        b.diffuse = b.ambient = base * ((1.0f - metallic) * (1.0f - t));
        b.transmit = base * ((1.0f - metallic) * t);
        b.ior = m.ior;
        if (std::isfinite(m.attenuation_distance))
            for (int k = 0; k < 3; ++k)
                b.absorption[k] =
                    -std::log(std::max(m.attenuation_color[k], 1e-30f)) / m.attenuation_distance;
        const float f0 = square((m.ior - 1.0f) / (m.ior + 1.0f));  // 0.04 at ior 1.5
        // KHR_materials_specular: the dielectric's F0 tinted (at most 1) and scaled by its
        // strength s, which is also its F90; a metal's F0 is its base colour, its F90 1.
        Color dielectric_f0(f0);
        float strength = 1.0f;
        if (m.specular.varies() || m.specular.value.r != 1.0f)
            strength = std::clamp(c(m.specular).r, 0.0f, 1.0f);
        if (m.specular_color.varies() || m.specular_color.value != Color(1.0f))
            dielectric_f0 =
                glm::min(dielectric_f0 * glm::max(c(m.specular_color), Color(0.0f)), Color(1.0f));
        b.specular = glm::mix(dielectric_f0 * strength, base, metallic);
        b.f90 = glm::mix(strength, 1.0f, metallic);
        if (m.has_coat()) {
            b.coat = std::clamp(c(m.clearcoat).r, 0.0f, 1.0f);
            b.coat_alpha =
                std::max(square(std::clamp(c(m.clearcoat_roughness).g, 0.0f, 1.0f)), kSmoothAlpha);
        }
        b.alpha = std::max(square(roughness), kSmoothAlpha);
        if (m.occlusion.varies() || m.occlusion.value.r != 1.0f)
            b.occlusion =
                std::clamp(1.0f + m.occlusion_strength * (c(m.occlusion).r - 1.0f), 0.0f, 1.0f);
        return b;
    }
    Bsdf operator()(const MirrorMaterial& m) const {
        Bsdf b;
        b.model = Bsdf::Model::Mirror;
        b.reflect = c(m.reflectance);
        return b;
    }
    Bsdf operator()(const DielectricMaterial& m) const {
        Bsdf b;
        b.model = Bsdf::Model::Dielectric;
        b.ior = m.ior;
        b.abbe = m.abbe;
        return b;
    }
    Bsdf operator()(const EmissiveMaterial& m) const {
        Bsdf b;
        b.model = Bsdf::Model::Emissive;
        b.emission = c(m.radiance);
        b.diffuse = b.ambient = c(m.albedo);
        return b;
    }
};

}  // namespace

bool Bsdf::has_lobes() const {
    switch (model) {
        case Model::Mirror:
        case Model::Dielectric:
            return false;
        case Model::Emissive:
            return !is_black(diffuse);
        case Model::Phong:
        case Model::BlinnPhong:
            return !is_black(diffuse) || !is_black(specular);
        default:
            return true;
    }
}

bool colour_sources(const Material& material, const ColorSource* out[3]) {
    // BsdfMaker's: a lambert material's ambient and diffuse are its albedo, a phong material's
    // are ka, kd and ks.
    if (!material.emission.is_black()) return false;  // make_bsdf adds the emission
    if (const auto* l = std::get_if<LambertMaterial>(&material.model)) {
        out[0] = out[1] = &l->albedo;
        out[2] = nullptr;
        return true;
    }
    if (const auto* p = std::get_if<PhongMaterial>(&material.model)) {
        if (p->shininess_map.varies()) return false;  // the shininess is not a colour
        out[0] = &p->ka;
        out[1] = &p->kd;
        out[2] = &p->ks;
        return true;
    }
    return false;
}

Bsdf make_bsdf(const Material& material, const Varyings& at,
               const std::vector<TextureImage>& textures) {
    return make_bsdf(material, at, TextureLookup{textures});
}

Bsdf make_bsdf(const Material& material, const Varyings& at, const TextureLookup& lookup) {
    Bsdf b = std::visit(BsdfMaker{at, lookup}, material.model);
    if (!material.emission.is_black()) b.emission += eval_color(material.emission, at, lookup);
    return b;
}

namespace {

/// GGX D times the height-correlated Smith visibility, D V (the specular lobe without its
/// Fresnel), for the unit normal n and half vector h, n.wi and n.wo.
float ggx_specular(vec3 n, vec3 h, float cos_i, float cos_o, float alpha) {
    const float a2 = alpha * alpha;
    const vec3 across = glm::cross(n, h);
    const float d = ggx_d(std::max(0.0f, glm::dot(n, h)), glm::dot(across, across), alpha);
    const float vis = 0.5f / (cos_i * std::sqrt(cos_o * cos_o * (1.0f - a2) + a2) +
                              cos_o * std::sqrt(cos_i * cos_i * (1.0f - a2) + a2));
    return d * vis;
}

}  // namespace

Color eval_bsdf(const Bsdf& b, vec3 n, vec3 wo, vec3 wi) {
    float cos_i = glm::dot(n, wi), cos_o = glm::dot(n, wo);
    if (cos_i <= 0.0f || cos_o <= 0.0f) return Color(0.0f);
    switch (b.model) {
        case Bsdf::Model::Lambert:
        case Bsdf::Model::Emissive:
            return b.diffuse * kInvPi;
        case Bsdf::Model::Phong: {
            if (is_black(b.specular)) return b.diffuse * kInvPi;
            float rv = std::max(0.0f, glm::dot(reflect(wi, n), wo));
            return b.diffuse * kInvPi +
                   b.specular * (phong_lobe_norm(b.shininess, false) * std::pow(rv, b.shininess));
        }
        case Bsdf::Model::BlinnPhong: {
            if (is_black(b.specular)) return b.diffuse * kInvPi;
            vec3 h = glm::normalize(wi + wo);
            float nh = std::max(0.0f, glm::dot(n, h));
            return b.diffuse * kInvPi +
                   b.specular * (phong_lobe_norm(b.shininess, true) * std::pow(nh, b.shininess));
        }
        case Bsdf::Model::OrenNayar: {
            // cos(phi_i - phi_o) from the projections of wi and wo onto the tangent plane.
            vec3 ti = wi - cos_i * n, to = wo - cos_o * n;
            float li = glm::length(ti), lo = glm::length(to);
            float cos_phi = li > 1e-6f && lo > 1e-6f ? glm::dot(ti, to) / (li * lo) : 0.0f;
            float sin_i = safe_sqrt(1.0f - cos_i * cos_i), sin_o = safe_sqrt(1.0f - cos_o * cos_o);
            // alpha = max(theta_i, theta_o), beta = min: sin(alpha) tan(beta).
            float sin_alpha, tan_beta;
            if (cos_i > cos_o) {  // theta_i < theta_o
                sin_alpha = sin_o;
                tan_beta = sin_i / cos_i;
            } else {
                sin_alpha = sin_i;
                tan_beta = sin_o / cos_o;
            }
            return b.diffuse * kInvPi *
                   (b.on_a + b.on_b * std::max(0.0f, cos_phi) * sin_alpha * tan_beta);
        }
        case Bsdf::Model::CookTorrance: {
            vec3 h = glm::normalize(wi + wo);
            float vh = std::max(0.0f, glm::dot(wo, h));
            Color f = specular_fresnel(b, vh);
            const Color base = (Color(1.0f) - f) * b.diffuse * kInvPi +
                               f * ggx_specular(n, h, cos_i, cos_o, b.alpha);
            if (b.coat <= 0.0f) return base;
            // The coat (glTF's KHR_materials_clearcoat): the base seen through it, less what
            // it reflects at the viewer's angle, plus its own GGX lobe of F0 0.04, about the
            // coat's own normal where it has one (both angles then measured from it).
            const vec3 nc = has_coat_normal(b) ? b.coat_normal : n;
            const float cos_oc = glm::dot(nc, wo), cos_ic = glm::dot(nc, wi);
            const Color seen = base * under_coat(b, std::clamp(cos_oc, 0.0f, 1.0f));
            if (cos_oc <= 0.0f || cos_ic <= 0.0f) return seen;
            return seen + Color(b.coat * coat_fresnel(vh) *
                                ggx_specular(nc, h, cos_ic, cos_oc, b.coat_alpha));
        }
        case Bsdf::Model::Mirror:
        case Bsdf::Model::Dielectric:
            return Color(0.0f);
    }
    return Color(0.0f);
}

float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    float cos_t = safe_sqrt(1.0f - sin2_t);
    float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

bool refract(vec3 wo, vec3 n, float eta, vec3& wt) {
    float cos_i = glm::dot(n, wo);
    float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    float cos_t = std::sqrt(1.0f - sin2_t);
    wt = -wo / eta + (cos_i / eta - cos_t) * n;
    return true;
}

}  // namespace svetlo
