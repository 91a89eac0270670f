// The light set: every light of a scene, built once and sampled the same way by every engine.
//
//   point, spot     delta in position: E = I / d^2 (times the spot's cone factor)
//   directional     delta in direction: E = irradiance
//   area            a one-sided emitting parallelogram (it is also drawn, as a visible quad)
//   emissive object every quad, mesh, sphere, box, cylinder and cone whose material emits:
//                   its emitting primitives, picked in proportion to area, then sampled
//                   uniformly by area (pdf_area = 1 / total area)
//
// Seen from a point p, a light made of a few flat faces (triangles, quads, a box's sides; at
// most kMaxFacingFaces, in more than one plane) is sampled over the faces whose front side p lies
// on, each picked in proportion to its area A times p's height h over its plane, then uniformly by
// area: the face's pdf_area is h / sum(A h), and its pdf per steradian d^3 / sum(A h). A box lamp
// sends no sample to its back faces, which emit nothing toward p, and few to the faces p sees
// edge-on: A h / d^3 is the face's solid angle seen from afar (docs/path.md, "Light
// sampling").
//
// A sample of a light with area estimates the irradiance by E = L cos' / (d^2 pdf_area), the
// area form of the rendering equation; its pdf per steradian is pdf_area d^2 / cos'. CSG and
// implicit surfaces with an emissive material are no lights: their area has no closed form to
// sample by (docs/scene-format.md). They glow where seen, and only the path tracer's BSDF
// samples find their light. Units:
// radiance W/(m^2 sr), irradiance W/m^2, pdfs per m^2 or per sr.
#pragma once

#include <vector>

#include "svetlo/geometry/geometry.h"
#include "svetlo/geometry/surface_sampling.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// A light as seen from a shading point p.
struct LightSample {
    vec3 p{0.0f};                // the point on the light (a point or spot light's position)
    vec3 n{0.0f};                // the unit emitting normal there (lights with area)
    vec3 wi{0.0f};               // unit, from p toward the light
    float distance = kInfinity;  // from p to the light (infinite for a directional light)
    Color irradiance{0.0f};      // W/m^2 on a surface facing wi, before occlusion
    float pdf = 1.0f;            // of wi, per steradian (1 for the delta lights)
    bool delta = true;           // a point, spot or directional light
};

/// A point on a light with area.
struct AreaPoint {
    SurfaceSample surface;  // point, front normal, uv
    Color radiance{0.0f};   // emitted toward the front side, W/(m^2 sr)
    float pdf_area = 0.0f;  // 1 / m^2
};

class LightSet {
public:
    /// A flat face of a light (light_set.cpp, sample()): its plane, n . x = offset with n
    /// its unit front normal, its area (m^2), and where in its primitive's u_part it lies.
    struct Face {
        vec3 n{0.0f};
        float offset = 0.0f;
        float area = 0.0f;
        uint32_t prim = 0;    // index into Source::prims
        float u_part = 0.0f;  // picks this face in sample_primitive
        /// A box's side in world space, corner + u edge_u + v edge_v, drawn without
        /// sample_primitive where its emission has no texture (edge_u zero: not a box's).
        vec3 corner{0.0f}, edge_u{0.0f}, edge_v{0.0f};
    };
    /// The faces a light may have to be sampled by the side a point sees.
    static constexpr size_t kMaxFacingFaces = 16;

    struct Source {
        bool delta = true;     // point, spot or directional (else a light with area)
        int light_index = -1;  // index into Scene::lights; -1 for an emissive object
        int object = -1;  // lights with area: index into Scene::objects, then area_light_quads()
        std::vector<uint32_t> prims;  // lights with area: primitives of the set's geometry
        uint32_t range_first = 0;     // the first primitive of its object in the set's geometry
        std::vector<float> cdf;       // cumulative weight over prims, ending at 1: area, or power
        // A textured emitter of many faces: each prim picked by the power it emits, its area
        // times the mean luminance of its emission (16 stratified points), so that the dark
        // parts of a glowing texture are seldom drawn; per prim, its density per m^2 (empty:
        // by area, 1 / area).
        std::vector<float> pdf_area;
        std::vector<vec3> normals;  // unit front normal per prim, when all are triangles
        float area = 0.0f;          // m^2
        std::vector<Face> faces;    // a few flat faces, in more than one plane
    };

    /// Throws Error for an emitter it cannot sample (an emissive plane, or an emissive shape
    /// under a non-uniform scale).
    explicit LightSet(const Scene& scene);

    /// The scene's materials, then one emissive material per area light.
    const std::vector<Material>& materials() const { return materials_; }
    /// The area lights as visible one-sided quads (with those materials): engines draw them.
    const std::vector<Object>& area_light_quads() const { return area_quads_; }
    /// Scene lights in their order, then emissive objects in theirs.
    const std::vector<Source>& sources() const { return sources_; }
    /// The source of Scene::lights[index], or null.
    const Source* source_of_light(int index) const;

    /// A point uniformly distributed by area on a light with area: u in [0,1)^2, u_pick in
    /// [0,1) chooses the primitive (and the face of a box, cylinder or cone).
    AreaPoint sample_area(const Source& source, vec2 u, float u_pick) const;
    /// The light as seen from p: for lights with area, a point drawn by sample_area(u,
    /// u_pick), or, for one with faces, over the faces p lies in front of (above).
    LightSample sample(const Source& source, vec3 p, vec2 u, float u_pick) const;
    /// A point on a light with area as seen from p; d^2 is clamped below by min_dist2 (the
    /// rasterizer's virtual point lights stand for a patch of that area). Its pdf is not set.
    LightSample sample_at(const AreaPoint& a, vec3 p, float min_dist2 = 0.0f) const;
    /// The pdf per steradian with which sample() picks the direction from p to the point q
    /// (normal nq) of a light with area: pdf_area d^2 / cos', 0 behind it.
    /// `prim`, the geometry's primitive that q lies on, matters for a source picked by power.
    float pdf(const Source& source, vec3 p, vec3 q, vec3 nq, uint32_t prim = ~0u) const;

private:
    /// The sum over the faces of `source` that p lies in front of of their area times p's
    /// height over their plane; with `face`, also the one of them that `pick` in [0,1) picks
    /// in proportion to that product.
    /// Picks a textured emitter's prims by the power they emit (Source::pdf_area).
    void weigh_by_power(Source& source) const;
    static float facing_weight(const Source& source, vec3 p, float pick = 0.0f,
                               const Face** face = nullptr);
    /// The emitted radiance of primitive `prim` at a point with varyings `at`.
    Color emission_at(uint32_t prim, const Varyings& at) const;

    const Scene& scene_;
    std::vector<Material> materials_;
    std::vector<Object> area_quads_;
    Geometry geometry_;  // the emitters' primitives, world space
    // Per material: the emitted radiance when it is constant (no texture), else evaluated
    // at each sample's uv.
    std::vector<Color> emission_;
    std::vector<char> emission_textured_;
    std::vector<Source> sources_;
};

// Inline: the rasterizer calls it for every virtual point light at every sample.
inline LightSample LightSet::sample_at(const AreaPoint& a, vec3 p, float min_dist2) const {
    LightSample s;
    s.delta = false;
    s.p = a.surface.p;
    s.n = a.surface.n;
    vec3 d = s.p - p;
    float dist2 = glm::dot(d, d);
    if (!(dist2 > 0.0f)) return s;
    s.distance = std::sqrt(dist2);
    s.wi = d * (1.0f / s.distance);
    float cos_light = -glm::dot(s.n, s.wi);
    if (cos_light <= 0.0f) return s;  // its back: it emits nothing this way
    // E = L cos' / (d^2 pdf_area): the area form of the rendering equation.
    s.irradiance = a.radiance * (cos_light / (std::max(dist2, min_dist2) * a.pdf_area));
    return s;  // pdf: left to sample(), which needs it (the rasterizer's VPLs do not)
}

}  // namespace svetlo
