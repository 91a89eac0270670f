#include "svetlo/geometry/scene_geometry.h"

namespace svetlo {

namespace {

void add_mesh(const Mesh& mesh, const Object& obj, Geometry& g) {
    auto base = static_cast<uint32_t>(g.positions.size());
    mat3 nm = normal_matrix(obj.transform.matrix);
    for (const vec3& p : mesh.positions) g.positions.push_back(obj.transform.point(p));
    if (!mesh.normals.empty() || !g.normals.empty()) {
        g.normals.resize(base, vec3(0.0f));
        for (const vec3& n : mesh.normals) {
            g.normals.push_back(obj.transform.is_identity ? n : glm::normalize(nm * n));
        }
        g.normals.resize(g.positions.size(), vec3(0.0f));
    }
    if (!mesh.uvs.empty() || !g.uvs.empty()) {
        g.uvs.resize(base, vec2(0.0f));
        g.uvs.insert(g.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
        g.uvs.resize(g.positions.size(), vec2(0.0f));
    }
    if (!mesh.uvs1.empty() || !g.uvs1.empty()) {  // set 1 is set 0 where a mesh has one set
        for (size_t v = g.uvs1.size(); v < base; ++v)
            g.uvs1.push_back(v < g.uvs.size() ? g.uvs[v] : vec2(0.0f));
        if (!mesh.uvs1.empty()) g.uvs1.insert(g.uvs1.end(), mesh.uvs1.begin(), mesh.uvs1.end());
        for (size_t v = g.uvs1.size(); v < g.positions.size(); ++v)
            g.uvs1.push_back(v < g.uvs.size() ? g.uvs[v] : vec2(0.0f));
    }
    if (!mesh.colors.empty() || !g.colors.empty()) {
        g.colors.resize(base, vec4(1.0f));
        g.colors.insert(g.colors.end(), mesh.colors.begin(), mesh.colors.end());
        g.colors.resize(g.positions.size(), vec4(1.0f));
    }
    if (!mesh.tangents.empty() || !g.tangents.empty()) {
        g.tangents.resize(base, vec4(0.0f));
        for (const vec4& t : mesh.tangents)
            g.tangents.push_back(transform_tangent(obj.transform, t));
        g.tangents.resize(g.positions.size(), vec4(0.0f));
    }
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) g.indices.push_back(base + mesh.indices[3 * t + k]);
        int m = obj.material >= 0 ? obj.material : mesh.face_material[t];
        g.triangle_material.push_back(static_cast<uint32_t>(m));
    }
}

}  // namespace

Geometry build_geometry(const std::vector<const Object*>& objects,
                        std::vector<PrimitiveRange>* ranges) {
    Geometry g;
    size_t triangles = 0;
    for (const Object* obj : objects) {
        if (const auto* mesh = std::get_if<Mesh>(&obj->shape)) triangles += mesh->triangle_count();
    }
    g.indices.reserve(3 * triangles);
    g.triangle_material.reserve(triangles);
    if (ranges) ranges->assign(objects.size(), {});
    for (size_t k = 0; k < objects.size(); ++k) {
        const Object& obj = *objects[k];
        const auto* mesh = std::get_if<Mesh>(&obj.shape);
        if (!mesh) continue;
        uint32_t first = g.triangle_count();
        add_mesh(*mesh, obj, g);
        if (ranges) (*ranges)[k] = {first, g.triangle_count()};
    }
    for (size_t k = 0; k < objects.size(); ++k) {
        const Object& obj = *objects[k];
        if (std::holds_alternative<Mesh>(obj.shape)) continue;
        g.shapes.push_back(
            make_analytic_shape(obj.shape, obj.transform, static_cast<uint32_t>(obj.material)));
        if (ranges) (*ranges)[k] = {g.primitive_count() - 1, g.primitive_count()};
    }
    return g;
}

Placement make_placement(uint32_t prototype, const Transform& to_world, int material,
                         const Bounds3& prototype_bounds) {
    Placement p;
    p.prototype = prototype;
    p.to_world = to_world;
    p.to_prototype = glm::inverse(to_world.matrix);
    p.normal_to_world = normal_matrix(to_world.matrix);
    p.mirrors = glm::determinant(mat3(to_world.matrix)) < 0.0f;
    p.material = material;
    // The corners of the prototype's box carried out, then widened by a few ulps of the box's
    // size: a point the local ray meets lies inside it despite the rounding of both transforms.
    p.bounds = transformed_bounds(prototype_bounds, to_world.matrix);
    if (!p.bounds.empty()) {
        const vec3 pad =
            1e-5f * (glm::abs(p.bounds.min) + glm::abs(p.bounds.max) + p.bounds.extent()) +
            vec3(1e-30f);
        p.bounds.min -= pad;
        p.bounds.max += pad;
    }
    return p;
}

void place_instances(const Scene& scene, Geometry& g) {
    std::vector<int> built(scene.prototypes.size(), -1);  // index in g.prototypes
    std::vector<Bounds3> bounds;                          // per built prototype, its own space
    for (const Instance& instance : scene.instances) {
        int& index = built[instance.prototype];
        if (index < 0) {
            auto prototype = std::make_shared<Geometry>(
                build_geometry(object_pointers(scene.prototypes[instance.prototype].objects)));
            bounds.push_back(prototype->bounds());
            index = static_cast<int>(g.prototypes.size());
            g.prototypes.push_back(std::move(prototype));
        }
        Placement p = make_placement(static_cast<uint32_t>(index), instance.transform,
                                     instance.material, bounds[static_cast<size_t>(index)]);
        g.placements.push_back(p);
    }
}

std::vector<const Object*> object_pointers(const std::vector<Object>& objects,
                                           const std::vector<Object>& more,
                                           const std::vector<Object>& last) {
    std::vector<const Object*> out;
    out.reserve(objects.size() + more.size() + last.size());
    for (const Object& o : objects) out.push_back(&o);
    for (const Object& o : more) out.push_back(&o);
    for (const Object& o : last) out.push_back(&o);
    return out;
}

}  // namespace svetlo
