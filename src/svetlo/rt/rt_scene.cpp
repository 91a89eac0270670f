#include "svetlo/rt/rt_scene.h"

#include "svetlo/core/error.h"

namespace svetlo {

namespace {

bool emits(const Material& m) {
    const auto* e = std::get_if<EmissiveMaterial>(&m);
    return e && !e->radiance.is_black();
}

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

void add_mesh(const Mesh& mesh, const Object& obj, Geometry& g) {
    auto base = static_cast<uint32_t>(g.positions.size());
    mat3 normal_matrix = glm::transpose(glm::inverse(mat3(obj.transform.matrix)));
    for (const vec3& p : mesh.positions) g.positions.push_back(obj.transform.point(p));
    if (!mesh.normals.empty() || !g.normals.empty()) {
        g.normals.resize(base, vec3(0.0f));
        for (const vec3& n : mesh.normals) {
            g.normals.push_back(obj.transform.is_identity ? n : glm::normalize(normal_matrix * n));
        }
        g.normals.resize(g.positions.size(), vec3(0.0f));
    }
    if (!mesh.uvs.empty() || !g.uvs.empty()) {
        g.uvs.resize(base, vec2(0.0f));
        g.uvs.insert(g.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
        g.uvs.resize(g.positions.size(), vec2(0.0f));
    }
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) g.indices.push_back(base + mesh.indices[3 * t + k]);
        int m = obj.material >= 0 ? obj.material : mesh.face_material[t];
        g.triangle_material.push_back(static_cast<uint32_t>(m));
    }
}

void finish_emitter(Emitter& e, const Geometry& g, std::vector<Emitter>& out) {
    if (e.prims.empty()) return;
    double total = 0.0;
    for (uint32_t id : e.prims) {
        total += primitive_area(g, id);
        e.cdf.push_back(static_cast<float>(total));
    }
    if (!(total > 0.0)) return;  // degenerate: nothing to sample
    for (float& c : e.cdf) c = static_cast<float>(c / total);
    e.cdf.back() = 1.0f;
    e.area = static_cast<float>(total);
    out.push_back(std::move(e));
}

}  // namespace

Geometry build_geometry(const Scene& scene, std::vector<Material>& materials,
                        std::vector<Emitter>& emitters) {
    Geometry g;
    materials = scene.materials;
    // Triangles first (their ids start at 0), then shapes; remember each object's range.
    size_t triangles = 0;
    for (const Object& obj : scene.objects) {
        if (const auto* mesh = std::get_if<Mesh>(&obj.shape)) triangles += mesh->triangle_count();
    }
    g.indices.reserve(3 * triangles);
    g.triangle_material.reserve(triangles);
    std::vector<std::pair<uint32_t, uint32_t>> mesh_ranges(scene.objects.size(), {0, 0});
    for (size_t k = 0; k < scene.objects.size(); ++k) {
        const Object& obj = scene.objects[k];
        if (const auto* mesh = std::get_if<Mesh>(&obj.shape)) {
            uint32_t first = g.triangle_count();
            add_mesh(*mesh, obj, g);
            mesh_ranges[k] = {first, g.triangle_count()};
        }
    }
    for (const Object& obj : scene.objects) {
        if (std::holds_alternative<Mesh>(obj.shape)) continue;
        g.shapes.push_back(
            make_analytic_shape(obj.shape, obj.transform, static_cast<uint32_t>(obj.material)));
    }
    // Area lights: visible, one-sided emissive quads with a material of their own.
    std::vector<std::pair<uint32_t, int>> area_lights;  // (primitive id, light index)
    for (size_t k = 0; k < scene.lights.size(); ++k) {
        const auto* a = std::get_if<AreaLight>(&scene.lights[k]);
        if (!a) continue;
        EmissiveMaterial m;
        m.radiance = ColorSource::constant(a->radiance);
        materials.push_back(m);
        g.shapes.push_back(make_analytic_shape(Quad{a->corner, a->edge_u, a->edge_v}, Transform{},
                                               static_cast<uint32_t>(materials.size() - 1)));
        area_lights.emplace_back(g.primitive_count() - 1, static_cast<int>(k));
    }
    // Emitters: one per area light, one per emissive object.
    for (auto [id, light] : area_lights) {
        Emitter e;
        e.prims.push_back(id);
        e.light_index = light;
        finish_emitter(e, g, emitters);
    }
    uint32_t shape_id = g.triangle_count();
    for (size_t k = 0; k < scene.objects.size(); ++k) {
        const Object& obj = scene.objects[k];
        Emitter e;
        if (std::holds_alternative<Mesh>(obj.shape)) {
            for (uint32_t t = mesh_ranges[k].first; t < mesh_ranges[k].second; ++t) {
                if (emits(materials[g.triangle_material[t]])) e.prims.push_back(t);
            }
        } else {
            uint32_t id = shape_id++;
            const AnalyticShape& s = g.shape(id);
            // CSG and implicit surfaces glow where seen but are not sampled as lights (their
            // surface area has no closed form); docs/scene-format.md says so.
            if (s.kind == ShapeKind::Csg || s.kind == ShapeKind::Implicit) continue;
            if (!emits(materials[static_cast<size_t>(obj.material)])) continue;
            if (s.kind == ShapeKind::Plane) {
                throw Error(scene.path.string(), obj.name,
                            "an emissive plane is infinite and cannot be a light; use a quad");
            }
            if (s.transformed && !is_similarity(s.to_world)) {
                throw Error(scene.path.string(), obj.name + ".transform",
                            "an emissive shape needs a uniform scale to be sampled as a light");
            }
            e.prims.push_back(id);
        }
        finish_emitter(e, g, emitters);
    }
    return g;
}

RtScene::RtScene(const Scene& scene, const std::string& accel, int threads) : scene_(scene) {
    geometry_ = build_geometry(scene, materials_, emitters_);
    for (size_t k = 0; k < scene.lights.size(); ++k) {
        if (!std::holds_alternative<AreaLight>(scene.lights[k]))
            punctual_.push_back(static_cast<int>(k));
    }
    unbounded_ = geometry_.unbounded_primitives();
    accel_ = make_accel(accel, geometry_, threads);
    if (!accel_) {
        throw Error(scene.path.string(), "render.accel",
                    accel == "embree" ? std::string("this svetlo was built without Embree")
                                      : "unknown accelerator '" + accel + "'");
    }
}

bool RtScene::intersect(const Ray& ray, Hit& hit) const {
    bool found = accel_->intersect(ray, hit);
    if (unbounded_.empty()) return found;
    if (!found) hit.t = ray.tmax;
    RayPrecomputed pre(ray);
    return geometry_.intersect(unbounded_.data(), unbounded_.size(), ray, pre, hit) || found;
}

bool RtScene::occluded(const Ray& ray) const {
    if (!unbounded_.empty() &&
        geometry_.occludes(unbounded_.data(), unbounded_.size(), ray, RayPrecomputed(ray))) {
        return true;
    }
    return accel_->occluded(ray);
}

}  // namespace svetlo
