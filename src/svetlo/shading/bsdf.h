// Materials as BRDFs. A Bsdf is a material with its textures evaluated at one surface point:
// a flat struct of colours and numbers plus free functions. All directions are unit
// vectors in world space pointing away from the surface; f is in 1/sr.
//
//   lambert       f = albedo / pi
//   phong         f = kd/pi + ks (n+2)/(2 pi) max(0, r.v)^n            (normalised Phong,
//   blinn_phong   f = kd/pi + ks (n+8)/(8 pi) max(0, n.h)^n             Lafortune & Willems 1994;
//                 (n+8)/(8 pi) is approximate: kd + ks = 1 can reflect 1.027 at n = 40;
//                 with ks, reflect and transmit black, make_bsdf gives lambert)
//   oren_nayar    f = albedo/pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta))
//                 (Oren & Nayar 1994, the qualitative model)
//   cook_torrance glTF 2.0 metallic-roughness: GGX D (Walter et al. 2007), height-correlated
//                 Smith V (Heitz 2014), Schlick F; diffuse (1 - F) c_diff / pi; its
//                 transmitted part (KHR_materials_transmission) refracts ideally at the
//                 smallest roughness and through GGX microfacets above it (Walter et al. 2007)
//   mirror        delta reflection, weight = reflectance
//   dielectric    delta reflection and refraction, chosen by the Fresnel reflectance
//
// sample_bsdf draws wi with its pdf (bsdf_sampling.cpp): cosine-weighted for the diffuse parts,
// the (n+1)/(2 pi) cos^n lobe about the mirror direction (Phong) or the half vector
// (Blinn-Phong), GGX visible normals (Heitz 2018) for Cook-Torrance, and the delta lobes
// (mirror, glass, phong's `reflect` and `transmit`) by their weights.
#pragma once

#include <algorithm>
#include <vector>

#include "svetlo/core/math.h"
#include "svetlo/scene/scene.h"
#include "svetlo/shading/mipmap.h"

namespace svetlo {

/// The least GGX alpha make_bsdf gives (roughness 0.032): below it the GGX peak exceeds float
/// range for point lights. A Cook-Torrance surface this smooth transmits by ideal refraction.
inline constexpr float kSmoothAlpha = 1e-3f;

struct Bsdf {
    enum class Model : unsigned char {
        Lambert,
        Phong,
        BlinnPhong,
        OrenNayar,
        CookTorrance,
        Mirror,
        Dielectric,
        Emissive
    };
    Model model = Model::Lambert;
    Color diffuse{0.0f};   // kd, albedo, or glTF's c_diff
    Color specular{0.0f};  // ks (Phong lobes) or F0 (Cook-Torrance)
    float f90 = 1.0f;      // Cook-Torrance: Fresnel at grazing (KHR_materials_specular)
    Color ambient{0.0f};   // k_a of the ambient term
    Color reflect{0.0f};   // ideal mirror part (phong reflect, mirror reflectance)
    Color transmit{0.0f};  // ideal transmission part (phong transmit)
    Color emission{0.0f};  // radiance emitted from the front side
    float shininess = 0.0f;
    float alpha = 0.0f;  // GGX roughness alpha = roughness^2
    float ior = 1.0f;
    float abbe = 0.0f;  // dielectric: the Abbe number V_d, 0 = no dispersion (path tracer)
    float on_a = 1.0f, on_b = 0.0f;  // Oren-Nayar A and B
    // What reaches the point of the ambient and environment light in the rasterizer and
    // Whitted (glTF's occlusion texture); the path tracer finds its own occlusion.
    float occlusion = 1.0f;
    // The absorption coefficient inside (1/scene unit) for a ray transmitted into the front
    // side: -ln(attenuation colour) / attenuation distance (Cook-Torrance with a volume).
    Color absorption{0.0f};
    // Cook-Torrance's clear coat: its strength and GGX alpha (0: none).
    float coat = 0.0f, coat_alpha = 0.0f;
    // The coat's own shading normal (world space, unit, turned toward the viewer as the
    // shading normal is: shading_frame.h), or zero: the coat takes the shading normal n.
    // Set by the engine that knows the point (coat_shading_normal, normal_map.h).
    vec3 coat_normal{0.0f};

    /// True when the BRDF has a non-delta part that direct lighting must evaluate.
    bool has_lobes() const;
};

/// The material at a point with varyings `at` (texture coordinates, vertex colour).
Bsdf make_bsdf(const Material& material, const Varyings& at,
               const std::vector<TextureImage>& textures);
/// The same with a texture footprint (trilinear filtering in the rasterizer).
Bsdf make_bsdf(const Material& material, const Varyings& at, const TextureLookup& lookup);

/// Where make_bsdf takes a lambert or phong material's ambient, diffuse and specular colours
/// from (out[0..2]; null: black), so that a renderer may evaluate them for many points at
/// once (eval_colors). False for another material.
bool colour_sources(const Material& material, const ColorSource* out[3]);

/// f(wo, wi) for a shading normal n; zero unless wo and wi are both above the surface.
Color eval_bsdf(const Bsdf& bsdf, vec3 n, vec3 wo, vec3 wi);

/// The albedo AOV: the diffuse colour of a material with lobes, else its mirror reflectance
/// (1 for glass).
inline Color albedo_of(const Bsdf& b) {
    if (b.has_lobes()) return b.diffuse;
    return b.model == Bsdf::Model::Dielectric ? Color(1.0f) : b.reflect;
}

/// GGX's distribution of normals for alpha at a half vector h of cosine cos_h and squared
/// sine sin2_h to the normal: alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2). The squared sine is
/// found from h's components across the normal (or |n x h|^2), not as 1 - cos^2, which keeps
/// no digits where h lies within alpha of n: near the smoothest alpha (kSmoothAlpha) the
/// peak's float noise made the path tracer's smooth reflections 11 % too bright.
inline float ggx_d(float cos_h, float sin2_h, float alpha) {
    const float a2 = alpha * alpha, q = a2 * cos_h * cos_h + sin2_h;
    return q > 0.0f ? a2 / (kPi * q * q) : 0.0f;  // q = 0: h along -n (clamped), or no h
}

/// Schlick's Fresnel: F0 + (F90 - F0) (1 - cos)^5 (F90 is 1 but for KHR_materials_specular).
inline Color fresnel_schlick(Color f0, float cos_theta, float f90 = 1.0f) {
    const float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
    return f0 + (Color(f90) - f0) * (m * m * m * m * m);
}

/// A Cook-Torrance surface's Fresnel reflectance at cos_theta = v.h, from its F0 and F90.
inline Color specular_fresnel(const Bsdf& b, float cos_theta) {
    return fresnel_schlick(b.specular, cos_theta, b.f90);
}

/// Whether the coat has a normal of its own (else it takes the shading normal).
inline bool has_coat_normal(const Bsdf& b) {
    return b.coat > 0.0f && glm::dot(b.coat_normal, b.coat_normal) > 0.0f;
}

/// The clear coat's Fresnel reflectance seen at cos_o = n.wo: its F0 is 0.04 (ior 1.5).
inline float coat_fresnel(float cos_o) { return fresnel_schlick(Color(0.04f), cos_o).r; }

/// What passes a Cook-Torrance surface's clear coat, both ways, seen at cos_o: 1 - coat F_c.
inline float under_coat(const Bsdf& b, float cos_o) {
    return b.coat > 0.0f ? 1.0f - b.coat * coat_fresnel(cos_o) : 1.0f;
}

/// What a Cook-Torrance surface transmits toward wo from behind it (its transmitted part
/// times what Fresnel leaves, 1 - F at cos_o = n.wo, under its coat): the weight of its
/// ideal refraction.
inline Color transmitted_weight(const Bsdf& b, float cos_o) {
    return b.transmit * (Color(1.0f) - specular_fresnel(b, cos_o)) * under_coat(b, cos_o);
}

/// Whether a Cook-Torrance surface's transmitted part is a rough one (a microfacet BTDF,
/// sampled by sample_bsdf and never by light sampling) rather than ideal refraction. At ior 1
/// no microfacet bends light, whatever its roughness: the light passes straight on.
inline bool rough_transmission(const Bsdf& b) {
    return b.model == Bsdf::Model::CookTorrance && b.alpha > kSmoothAlpha && b.ior != 1.0f &&
           !is_black(b.transmit);
}

/// The medium a ray enters when it is transmitted through a surface from the side `front`
/// says: the material's absorption going in through the front, none coming out of the back.
inline Color medium_after(const Bsdf& b, bool front) { return front ? b.absorption : Color(0.0f); }

/// What a medium of absorption `sigma` (1/scene unit) leaves of light that crosses `distance`
/// of it (Beer-Lambert); 0 across an infinite distance.
inline Color transmittance(Color sigma, float distance) {
    if (is_black(sigma)) return Color(1.0f);
    return glm::exp(-sigma * distance);
}

/// A direction drawn from a BSDF.
struct BsdfSample {
    vec3 wi{0.0f};       // unit, world space, away from the surface
    Color f{0.0f};       // f(wo, wi) of the non-delta lobes (0 for a delta lobe)
    Color weight{0.0f};  // f |cos| / pdf: what the sample multiplies incoming radiance by
    float pdf = 0.0f;    // per steradian; for a delta lobe, the probability of choosing it
    // A direction that light sampling never draws, so that what it reaches counts in full
    // (no MIS): a mirror or refraction direction, or a rough refraction (its pdf then per
    // steradian, as pdf_transmitted gives it).
    bool delta = false;
    bool valid() const { return pdf > 0.0f; }
};

/// Draws wi for wo. n is the shading normal turned toward wo (shading_frame.h); `front` says
/// whether wo lies on the surface's front side (glass is entered from the front). u in
/// [0,1)^2 samples the lobe, u_lobe in [0,1) picks it.
BsdfSample sample_bsdf(const Bsdf& bsdf, vec3 n, vec3 wo, bool front, vec2 u, float u_lobe);

/// The pdf per steradian with which sample_bsdf draws wi through its non-delta lobes.
float pdf_bsdf(const Bsdf& bsdf, vec3 n, vec3 wo, vec3 wi);

/// The rough transmitted part of a Cook-Torrance surface (rough_transmission), for wo on the
/// side n faces and `front` as sample_bsdf takes it: f(wo, wi) per steradian, and the pdf per
/// steradian with which sample_bsdf draws wi through it, the lobe's probability included.
/// For wi below the surface, the microfacet BTDF of Walter et al. 2007 with GGX visible
/// normals and the height-correlated Smith G (pbrt-v4, section 9.7), its Fresnel glTF's
/// Schlick at wo.m; not divided by eta^2 across the interface, as the ideal refraction is
/// not. For wi above, the share of microfacets that reflect wo totally (inside a denser
/// medium), which reflect the transmitted part instead, as the ideal refraction does.
Color eval_transmitted(const Bsdf& bsdf, vec3 n, vec3 wo, vec3 wi, bool front);
float pdf_transmitted(const Bsdf& bsdf, vec3 n, vec3 wo, vec3 wi, bool front);

/// Unpolarised Fresnel reflectance of a dielectric interface. cos_i is the cosine of the
/// incident angle (> 0), eta = n_transmitted / n_incident. Returns 1 under total internal
/// reflection.
float fresnel_dielectric(float cos_i, float eta);

/// Mirror of wo (pointing away) about n.
inline vec3 reflect(vec3 wo, vec3 n) { return 2.0f * glm::dot(wo, n) * n - wo; }

/// The normalisation of the (Blinn-)Phong lobe of exponent n, so that it integrates to ks:
/// (n + 2) / (2 pi) for Phong's (r.v)^n, (n + 8) / (8 pi) for Blinn-Phong's (n.h)^n.
inline float phong_lobe_norm(float n, bool blinn) {
    return blinn ? (n + 8.0f) / (8.0f * kPi) : (n + 2.0f) / (2.0f * kPi);
}

/// Refracts wo (pointing away, on n's side) through an interface with eta = n_t / n_i. Returns
/// false under total internal reflection.
bool refract(vec3 wo, vec3 n, float eta, vec3& wt);

}  // namespace svetlo
