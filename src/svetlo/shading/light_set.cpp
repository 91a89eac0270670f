#include "svetlo/shading/light_set.h"

#include <algorithm>
#include <array>

#include "svetlo/core/error.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/scene/material_sources.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/cutouts.h"
#include "svetlo/shading/lights.h"

namespace svetlo {

namespace {

/// True when the linear part is a rotation times a uniform scale (areas scale uniformly).
bool is_similarity(const mat4& m) {
    mat3 a(m);
    mat3 g = glm::transpose(a) * a;
    float s = (g[0][0] + g[1][1] + g[2][2]) / 3.0f;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (std::abs(g[i][j] - (i == j ? s : 0.0f)) > 1e-4f * s) return false;
        }
    }
    return true;
}

/// Lists the flat faces of a source made of triangles, quads and boxes, when there are at
/// most kMaxFacingFaces of them, in more than one plane.
void add_faces(LightSet::Source& s, const Geometry& g) {
    std::vector<LightSet::Face> faces;
    for (uint32_t k = 0; k < s.prims.size(); ++k) {
        const uint32_t id = s.prims[k];
        const float area = primitive_area(g, id);
        // The primitive's faces: each one's share of its area and the u_part at its middle,
        // and a box's side as a parallelogram in world space.
        std::vector<LightSet::Face> parts;
        if (g.is_triangle(id) || g.shape(id).kind == ShapeKind::Quad) {
            parts.push_back({.area = area, .prim = k, .u_part = 0.5f});
        } else if (g.shape(id).kind == ShapeKind::Box) {
            // The sides in sample_primitive's order, each one's share of the area.
            const AnalyticShape& box = g.shape(id);
            BoxSide sides[6];
            for (int f = 0; f < 6; ++f) sides[f] = box_side(box.p0, box.p1, f);
            const float total = 2.0f * (sides[0].area + sides[2].area + sides[4].area);
            float before = 0.0f;
            for (const BoxSide& b : sides) {
                LightSet::Face side{.area = b.area / total * area, .prim = k};
                side.u_part = (before + 0.5f * b.area) / total;
                before += b.area;
                side.corner =
                    box.transformed ? vec3(box.to_world * vec4(b.corner, 1.0f)) : b.corner;
                side.edge_u = box.transformed ? mat3(box.to_world) * b.edge_u : b.edge_u;
                side.edge_v = box.transformed ? mat3(box.to_world) * b.edge_v : b.edge_v;
                parts.push_back(side);
            }
        } else {
            return;  // curved: not flat faces
        }
        for (LightSet::Face& f : parts) {
            if (faces.size() == LightSet::kMaxFacingFaces) return;
            const SurfaceSample at = sample_primitive(g, id, vec2(0.5f), f.u_part);
            f.n = at.n;
            f.offset = glm::dot(at.n, at.p);
            if (f.area > 0.0f) faces.push_back(f);
        }
    }
    if (faces.empty()) return;
    // Faces in one plane change nothing: p sees the front of all of them or of none, and
    // they are sampled by area as before (a quad light made of two triangles).
    const LightSet::Face& first = faces.front();
    const bool one_plane = std::all_of(faces.begin(), faces.end(), [&](const LightSet::Face& f) {
        return glm::dot(f.n, first.n) > 1.0f - 1e-5f &&
               std::abs(f.offset - first.offset) <= 1e-5f * (1.0f + std::abs(first.offset));
    });
    if (!one_plane) s.faces = std::move(faces);
}

/// Fills a source's area CDF over its primitives; false when it has no area.
bool finish_source(LightSet::Source& s, const Geometry& g) {
    double total = 0.0;
    for (uint32_t id : s.prims) {
        total += primitive_area(g, id);
        s.cdf.push_back(static_cast<float>(total));
    }
    if (!(total > 0.0)) return false;  // degenerate: nothing to sample
    for (float& c : s.cdf) c = static_cast<float>(c / total);
    s.cdf.back() = 1.0f;
    s.area = static_cast<float>(total);
    add_faces(s, g);
    // Triangles keep their normals (sample_area): no normalisation per sample.
    if (!std::all_of(s.prims.begin(), s.prims.end(),
                     [&](uint32_t id) { return g.is_triangle(id); }))
        return true;
    for (uint32_t id : s.prims) {
        const uint32_t* t = &g.indices[3 * static_cast<size_t>(id)];
        s.normals.push_back(
            triangle_normal(g.positions[t[0]], g.positions[t[1]], g.positions[t[2]]));
    }
    return true;
}

/// Whether an object is one of the light set's emitters: some material of it emits, and it
/// is neither CSG nor implicit (they glow but are no lights; see the header). Throws for the
/// emitters that cannot be sampled: a plane, a shape scaled unevenly.
bool is_light(const Object& obj, const std::vector<Material>& materials, const Scene& scene) {
    bool any = false;
    if (const auto* mesh = std::get_if<Mesh>(&obj.shape); mesh && obj.material < 0) {
        for (int m : mesh->face_material) any = any || emits(materials[static_cast<size_t>(m)]);
    } else if (obj.material >= 0) {
        any = emits(materials[static_cast<size_t>(obj.material)]);
    }
    if (!any || std::holds_alternative<Csg>(obj.shape) ||
        std::holds_alternative<Implicit>(obj.shape)) {
        return false;
    }
    if (std::holds_alternative<Plane>(obj.shape)) {
        throw Error(scene.path.string(), obj.name,
                    "an emissive plane is infinite and cannot be a light; use a quad");
    }
    // Meshes and quads are baked into world space; the other shapes are sampled in their own.
    bool baked = std::holds_alternative<Mesh>(obj.shape) || std::holds_alternative<Quad>(obj.shape);
    if (!baked && !obj.transform.is_identity && !is_similarity(obj.transform.matrix)) {
        throw Error(scene.path.string(), obj.name + ".transform",
                    "an emissive shape needs a uniform scale to be sampled as a light");
    }
    return true;
}

}  // namespace

LightSet::LightSet(const Scene& scene) : scene_(scene), materials_(scene.materials) {
    // Area lights: visible, one-sided emissive quads with a material of their own.
    for (const Light& light : scene.lights) {
        const auto* a = std::get_if<AreaLight>(&light);
        if (!a) continue;
        EmissiveMaterial m;
        m.radiance = ColorSource::constant(a->radiance);
        materials_.push_back(m);
        Object quad;
        quad.name = "lights[" + std::to_string(&light - scene.lights.data()) + "]";
        quad.shape = Quad{a->corner, a->edge_u, a->edge_v};
        quad.material = static_cast<int>(materials_.size() - 1);
        area_quads_.push_back(std::move(quad));
    }
    // The emitters' geometry: every emissive object, then the area lights' quads.
    std::vector<const Object*> emitters;
    std::vector<int> emitter_object;  // per emitter, its index among objects and quads
    for (const Object& obj : scene.objects) {
        if (!is_light(obj, materials_, scene)) continue;
        emitters.push_back(&obj);
        emitter_object.push_back(static_cast<int>(&obj - scene.objects.data()));
    }
    for (const Material& m : materials_) {
        // What make_bsdf emits: an emissive material's radiance plus any material's emission.
        const auto* e = std::get_if<EmissiveMaterial>(&m.model);
        // A cutout emitter too: its holes emit nothing (emission_at).
        const bool textured =
            (e && e->radiance.varies()) || m.emission.varies() || m.alpha.active();
        emission_textured_.push_back(textured);
        emission_.push_back(textured ? Color(0.0f)
                                     : (e ? e->radiance.value : Color(0.0f)) + m.emission.value);
    }
    const size_t object_emitters = emitters.size();
    for (const Object& quad : area_quads_) emitters.push_back(&quad);
    std::vector<PrimitiveRange> ranges;
    geometry_ = build_geometry(emitters, &ranges);

    int area_light = 0;
    for (size_t k = 0; k < scene.lights.size(); ++k) {
        Source s;
        s.light_index = static_cast<int>(k);
        if (std::holds_alternative<AreaLight>(scene.lights[k])) {
            s.delta = false;
            s.object = static_cast<int>(scene.objects.size()) + area_light;
            s.prims.push_back(ranges[object_emitters + static_cast<size_t>(area_light++)].first);
            if (!finish_source(s, geometry_)) continue;  // no area: it emits nothing
        }
        sources_.push_back(std::move(s));
    }
    for (size_t k = 0; k < object_emitters; ++k) {
        Source s;
        s.delta = false;
        s.object = emitter_object[k];
        bool textured = false;
        s.range_first = ranges[k].first;
        for (uint32_t id = ranges[k].first; id < ranges[k].end; ++id) {
            if (emits(materials_[geometry_.material(id)])) {
                s.prims.push_back(id);
                textured = textured || emission_textured_[geometry_.material(id)];
            }
        }
        if (!finish_source(s, geometry_)) continue;
        if (textured && s.faces.empty() && s.prims.size() > 1) weigh_by_power(s);
        sources_.push_back(std::move(s));
    }
}

const LightSet::Source* LightSet::source_of_light(int index) const {
    for (const Source& s : sources_) {
        if (s.light_index == index) return &s;
    }
    return nullptr;
}

AreaPoint LightSet::sample_area(const Source& source, vec2 u, float u_pick) const {
    // Pick a primitive by area, then reuse the remainder of u_pick for the shape's face.
    size_t k = static_cast<size_t>(std::upper_bound(source.cdf.begin(), source.cdf.end(), u_pick) -
                                   source.cdf.begin());
    k = std::min(k, source.prims.size() - 1);
    float lo = k == 0 ? 0.0f : source.cdf[k - 1];
    float width = source.cdf[k] - lo;
    float u_rest = width > 0.0f ? std::clamp((u_pick - lo) / width, 0.0f, 0.99999994f) : 0.5f;
    uint32_t prim = source.prims[k];
    AreaPoint a;
    a.surface = source.normals.empty()
                    ? sample_primitive(geometry_, prim, u, u_rest)
                    : sample_triangle_primitive(geometry_, prim, u, source.normals[k]);
    a.pdf_area = source.pdf_area.empty() ? 1.0f / source.area : source.pdf_area[k];
    a.radiance = emission_at(prim, a.surface.at);
    return a;
}

void LightSet::weigh_by_power(Source& s) const {
    constexpr int kSide = 4;  // 16 stratified points a prim
    std::vector<double> weight(s.prims.size());
    double total = 0.0, area = 0.0;
    for (size_t k = 0; k < s.prims.size(); ++k) {
        const uint32_t prim = s.prims[k];
        double lum = 0.0;
        for (int a = 0; a < kSide; ++a) {
            for (int b = 0; b < kSide; ++b) {
                const vec2 u((a + 0.5f) / kSide, (b + 0.5f) / kSide);
                const Varyings at =
                    s.normals.empty()
                        ? sample_primitive(geometry_, prim, u, 0.5f).at
                        : sample_triangle_primitive(geometry_, prim, u, s.normals[k]).at;
                lum += luminance(emission_at(prim, at));
            }
        }
        const double prim_area = primitive_area(geometry_, prim);
        weight[k] = prim_area * lum / (kSide * kSide);
        total += weight[k];
        area += prim_area;
    }
    // No prim may have density zero (16 points can miss a texel that glows): a floor of
    // 1e-3 of the mean power per m^2.
    const double floor = total > 0.0 ? 1e-3 * total / area : 1.0;
    double sum = 0.0;
    for (size_t k = 0; k < s.prims.size(); ++k) {
        weight[k] += floor * primitive_area(geometry_, s.prims[k]);
        sum += weight[k];
    }
    double running = 0.0;
    s.pdf_area.resize(s.prims.size());
    for (size_t k = 0; k < s.prims.size(); ++k) {
        running += weight[k];
        s.cdf[k] = static_cast<float>(running / sum);
        s.pdf_area[k] = static_cast<float>(weight[k] / sum / primitive_area(geometry_, s.prims[k]));
    }
    s.cdf.back() = 1.0f;
}

Color LightSet::emission_at(uint32_t prim, const Varyings& at) const {
    const uint32_t m = geometry_.material(prim);
    if (!emission_textured_[m]) return emission_[m];
    const Material& material = materials_[m];
    const Color emitted = make_bsdf(material, at, scene_.textures).emission;
    return material.alpha.active() ? emitted * mean_cover(material.alpha, at, scene_.textures)
                                   : emitted;
}

float LightSet::facing_weight(const Source& source, vec3 p, float pick, const Face** face) {
    std::array<float, kMaxFacingFaces> cdf;
    float total = 0.0f;
    for (size_t f = 0; f < source.faces.size(); ++f) {
        const Face& x = source.faces[f];
        const float height = glm::dot(x.n, p) - x.offset;  // p's height over the face's plane
        if (height > 0.0f) total += x.area * height;
        cdf[f] = total;
    }
    if (!face || !(total > 0.0f)) return total;
    // The first face whose cumulative weight passes pick's share (one behind p adds none).
    const float target = pick * total;
    size_t f = 0;
    while (f + 1 < source.faces.size() && !(target < cdf[f])) ++f;
    *face = &source.faces[f];
    return total;
}

LightSample LightSet::sample(const Source& source, vec3 p, vec2 u, float u_pick) const {
    if (!source.delta) {
        const Face* face = nullptr;
        const float weight = source.faces.empty() ? 0.0f : facing_weight(source, p, u_pick, &face);
        AreaPoint a;
        if (!face) {  // by area over all (p sees no face's front: a sample that brings nothing)
            a = sample_area(source, u, u_pick);
        } else {
            const uint32_t prim = source.prims[face->prim];
            if (face->edge_u != vec3(0.0f) && !emission_textured_[geometry_.material(prim)]) {
                // A box's side: the parallelogram sample_primitive would map u onto.
                a.surface.p = face->corner + u.x * face->edge_u + u.y * face->edge_v;
                a.surface.n = face->n;
            } else {
                a.surface =
                    source.normals.empty()
                        ? sample_primitive(geometry_, prim, u, face->u_part)
                        : sample_triangle_primitive(geometry_, prim, u, source.normals[face->prim]);
            }
            a.pdf_area = (glm::dot(face->n, p) - face->offset) / weight;
            a.radiance = emission_at(prim, a.surface.at);
        }
        LightSample s = sample_at(a, p);
        if (!face && !source.faces.empty()) s.irradiance = Color(0.0f);  // as pdf() says
        // pdf(): pdf_area d^2 / cos', from what sample_at found.
        if (!is_black(s.irradiance))
            s.pdf = a.pdf_area * s.distance * s.distance / -glm::dot(s.n, s.wi);
        return s;
    }
    const Light& light = scene_.lights[static_cast<size_t>(source.light_index)];
    PunctualSample ps = sample_punctual(light, p);
    LightSample s;
    s.wi = ps.wi;
    s.distance = ps.distance;
    s.p = std::isinf(ps.distance) ? p : p + ps.wi * ps.distance;
    s.irradiance = ps.irradiance;
    return s;
}

float LightSet::pdf(const Source& source, vec3 p, vec3 q, vec3 nq, uint32_t prim) const {
    if (source.delta) return 0.0f;
    vec3 d = q - p;
    float dist2 = glm::dot(d, d);
    float cos_light = -glm::dot(nq, d) / std::sqrt(dist2);
    if (!(dist2 > 0.0f) || cos_light <= 0.0f) return 0.0f;
    if (!source.pdf_area.empty()) {  // by power: the prim's own density
        const auto at = std::lower_bound(source.prims.begin(), source.prims.end(), prim);
        if (at == source.prims.end() || *at != prim) return 0.0f;
        return dist2 * source.pdf_area[static_cast<size_t>(at - source.prims.begin())] / cos_light;
    }
    if (source.faces.empty()) return dist2 / (cos_light * source.area);
    // The face's pdf_area, its height over the plane over the weight, p's height being
    // cos' d: d^3 / weight per steradian.
    const float weight = facing_weight(source, p);
    return weight > 0.0f ? dist2 * std::sqrt(dist2) / weight : 0.0f;
}

}  // namespace svetlo
