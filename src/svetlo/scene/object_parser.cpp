// lights and objects sections, transforms, and mesh files.
#include <algorithm>
#include <glm/gtc/type_ptr.hpp>

#include "svetlo/core/image_io.h"
#include "svetlo/scene/instances.h"
#include "svetlo/scene/material_sources.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene_parts.h"

namespace svetlo {

namespace {

int find_material(const Scene& scene, const JsonNode& node) {
    std::string name = node.as_string();
    for (size_t k = 0; k < scene.material_names.size(); ++k) {
        if (scene.material_names[k] == name) return static_cast<int>(k);
    }
    node.fail("unknown material '" + name + "'");
}

/// `light` carried by `t`: a mesh file's glTF light placed by its object, or a prototype's by
/// its instance.
Light transformed(Light light, const Transform& t) {
    std::visit(
        [&](auto& l) {
            if constexpr (requires { l.position; }) l.position = t.point(l.position);
            if constexpr (requires { l.direction; })
                l.direction = glm::normalize(t.vector(l.direction));
            if constexpr (requires { l.corner; }) {
                l.corner = t.point(l.corner);
                l.edge_u = t.vector(l.edge_u);
                l.edge_v = t.vector(l.edge_v);
            }
        },
        light);
    return light;
}

/// Reads an array of vectors given either nested ([[x,y,z], ...]) or flat ([x,y,z, ...]).
template <int N>
std::vector<glm::vec<N, float>> parse_vectors(const JsonNode& node) {
    std::vector<glm::vec<N, float>> out;
    size_t n = node.size();
    bool nested = n > 0 && node.at(size_t{0}).is_array();
    if (!nested && n % N != 0) node.fail("length must be a multiple of " + std::to_string(N));
    for (size_t k = 0; k < (nested ? n : n / N); ++k) {
        if (nested && node.at(k).size() != N)
            node.at(k).fail("must have " + std::to_string(N) + " numbers");
        glm::vec<N, float> v;
        for (int c = 0; c < N; ++c) {
            v[c] = (nested ? node.at(k).at(static_cast<size_t>(c)) : node.at(N * k + c)).as_float();
        }
        out.push_back(v);
    }
    return out;
}

void check_non_degenerate_quad(const JsonNode& node, vec3 u, vec3 v) {
    if (glm::length(glm::cross(u, v)) <= 0.0f) node.fail("edge_u and edge_v are parallel or zero");
}

/// The scene's indices of a mesh file's textures, added once per file however many objects
/// name it, within the scene's texture memory (kMaxSceneTextureBytes).
std::vector<int> add_file_textures(const JsonNode& node, const std::filesystem::path& file,
                                   const MeshFile& loaded, Scene& scene) {
    std::vector<int> out;
    size_t left = texture_bytes_left(scene);
    for (size_t k = 0; k < loaded.textures.size(); ++k) {
        const std::string source =
            file.lexically_normal().string() + "#texture" + std::to_string(k);
        auto known = std::find(scene.texture_sources.begin(), scene.texture_sources.end(), source);
        if (known != scene.texture_sources.end()) {
            out.push_back(static_cast<int>(known - scene.texture_sources.begin()));
            continue;
        }
        if (loaded.textures[k].bytes() > left)
            node.fail("the scene's textures would take more than " +
                      std::to_string(kMaxSceneTextureBytes >> 20) + " MiB");
        left -= loaded.textures[k].bytes();
        scene.textures.push_back(loaded.textures[k]);
        scene.texture_sources.push_back(source);
        out.push_back(static_cast<int>(scene.textures.size()) - 1);
    }
    return out;
}

/// A mesh file's shared mesh (MeshFile::Shared) as the scene holds it: a prototype, and
/// where the file's nodes place it in the file's space.
struct SharedPlaces {
    uint32_t prototype = 0;
    std::vector<mat4> places;
};

/// What `smooth` and `material` say of a mesh, after its file's materials are in the scene
/// from `offset` on: vertex normals kept, made or dropped; the file's faces given the scene's
/// materials (none where `material` replaces them; a grey Lambertian where the file gave none).
void finish_mesh(Mesh& mesh, const JsonNode& node, Scene& scene, int material, int offset) {
    for (int& m : mesh.face_material) m = m >= 0 ? m + offset : -1;
    if (auto n = node.find("smooth")) mesh.smooth = n->as_bool();
    if (!mesh.smooth) {
        mesh.normals.clear();
    } else if (mesh.normals.empty()) {
        compute_vertex_normals(mesh);
    }  // a zero vertex normal (a glTF primitive without NORMAL) stays: the triangle's own
    if (material >= 0 || mesh.indices.empty()) {
        mesh.face_material.clear();
    } else if (mesh.face_material.empty()) {
        node.at("material");  // fails with "missing key": the file brings no material
    } else {
        // Faces the file left without a material get a plain grey Lambertian one.
        for (int& m : mesh.face_material) {
            if (m < 0) {
                scene.materials.push_back(LambertMaterial{});
                scene.material_names.push_back(node.path() + ":default");
                m = static_cast<int>(scene.materials.size()) - 1;
                for (int& rest : mesh.face_material) rest = rest < 0 ? m : rest;
            }
        }
    }
}

/// A `mesh` object's triangles: its file's (the meshes one node places, baked) or its own.
/// A glTF mesh that several nodes place becomes a prototype of the scene, and its places go
/// to `shared`; where `shared` is null (a CSG child, which must be one mesh) such a file is
/// refused.
Mesh parse_mesh(const JsonNode& node, Scene& scene, FileCache& meshes, int material,
                const Transform& transform, std::vector<SharedPlaces>* shared) {
    Mesh mesh;
    int offset = 0;
    if (auto file_node = node.find("file")) {
        if (node.has("positions")) node.fail("give either file or positions, not both");
        const std::filesystem::path file = named_file(*file_node, scene);
        std::shared_ptr<const MeshFile> read;
        try {
            read = meshes.read(file, scene.files);
        } catch (const std::exception& e) {
            file_node->fail("cannot read mesh '" + file_node->as_string() + "': " + e.what());
        }
        const MeshFile& loaded = *read;
        mesh = loaded.mesh;
        if (!loaded.shared.empty() && !shared)
            file_node->fail("'" + file_node->as_string() +
                            "' places one mesh at several nodes (instances); a CSG child must "
                            "be one mesh");
        for (const std::string& e : loaded.extensions)
            if (std::find(scene.extensions.begin(), scene.extensions.end(), e) ==
                scene.extensions.end())
                scene.extensions.push_back(e);
        for (const std::string& w : loaded.warnings)
            scene.warnings.push_back(file_node->path() + ": '" + file_node->as_string() +
                                     "': " + w);
        offset = static_cast<int>(scene.materials.size());
        const std::vector<int> textures = add_file_textures(*file_node, file, loaded, scene);
        for (size_t k = 0; k < loaded.materials.size(); ++k) {
            Material m = loaded.materials[k];
            any_source(m, [&](ColorSource& s) {
                if (s.kind == ColorSource::Kind::Image)
                    s.texture = textures[static_cast<size_t>(s.texture)];
                return false;
            });
            scene.materials.push_back(std::move(m));
            scene.material_names.push_back(node.path() + ":" + loaded.material_names[k]);
        }
        for (const Light& l : loaded.lights)  // glTF lights move with the object
            scene.lights.push_back(transformed(l, transform));
        for (size_t k = 0; k < loaded.shared.size(); ++k) {
            Object part;
            part.name = node.path() + ":mesh" + std::to_string(k);
            part.shape = loaded.shared[k].mesh;
            part.material = material;
            finish_mesh(std::get<Mesh>(part.shape), node, scene, material, offset);
            scene.prototypes.push_back({part.name, {std::move(part)}});
            shared->push_back(
                {static_cast<uint32_t>(scene.prototypes.size() - 1), loaded.shared[k].places});
        }
    } else {
        mesh.positions = parse_vectors<3>(node.at("positions"));
        JsonNode indices = node.at("indices");
        for (size_t k = 0; k < indices.size(); ++k) {
            auto i = indices.at(k).as_integer(0, static_cast<long long>(mesh.positions.size()) - 1);
            mesh.indices.push_back(static_cast<uint32_t>(i));
        }
        if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
            indices.fail("must hold a positive multiple of 3 vertex indices");
        }
        if (auto n = node.find("normals")) {
            mesh.normals = parse_vectors<3>(*n);
            if (mesh.normals.size() != mesh.positions.size())
                n->fail("needs one normal per position");
        }
        if (auto n = node.find("uvs")) {
            mesh.uvs = parse_vectors<2>(*n);
            if (mesh.uvs.size() != mesh.positions.size()) n->fail("needs one uv per position");
        }
    }
    finish_mesh(mesh, node, scene, material, offset);
    return mesh;
}

}  // namespace

Light parse_light(const JsonNode& node) {
    if (!node.is_object()) node.fail("must be an object");
    std::string type = node.at("type").as_choice({"point", "directional", "spot", "area"});
    if (type == "point") {
        node.expect_object({"type", "position", "intensity"});
        return PointLight{node.at("position").as_vec3(), node.at("intensity").as_color()};
    }
    if (type == "directional") {
        node.expect_object({"type", "direction", "irradiance"});
        return DirectionalLight{node.at("direction").as_direction(),
                                node.at("irradiance").as_color()};
    }
    if (type == "spot") {
        node.expect_object(
            {"type", "position", "direction", "intensity", "inner_angle", "outer_angle"});
        SpotLight s;
        s.position = node.at("position").as_vec3();
        s.direction = node.at("direction").as_direction();
        s.intensity = node.at("intensity").as_color();
        s.inner_deg = node.at("inner_angle").as_in_range(0.0, 180.0);
        s.outer_deg = node.at("outer_angle").as_in_range(0.0, 180.0);
        if (s.outer_deg < s.inner_deg) node.at("outer_angle").fail("must be >= inner_angle");
        return s;
    }
    node.expect_object({"type", "corner", "edge_u", "edge_v", "radiance"});
    AreaLight a;
    a.corner = node.at("corner").as_vec3();
    a.edge_u = node.at("edge_u").as_vec3();
    a.edge_v = node.at("edge_v").as_vec3();
    check_non_degenerate_quad(node, a.edge_u, a.edge_v);
    a.radiance = node.at("radiance").as_color();
    return a;
}

Transform parse_transform(const JsonNode& node) {
    Transform t;
    if (node.has("matrix")) {
        node.expect_object({"matrix"});
        JsonNode m = node.at("matrix");
        if (m.size() != 16) m.fail("must hold 16 numbers (row-major)");
        for (int row = 0; row < 4; ++row) {
            for (int col = 0; col < 4; ++col)
                t.matrix[col][row] = m.at(static_cast<size_t>(4 * row + col)).as_float();
        }
        if (t.matrix[0][3] != 0.0f || t.matrix[1][3] != 0.0f || t.matrix[2][3] != 0.0f ||
            t.matrix[3][3] != 1.0f) {
            m.fail("must be affine (last row 0 0 0 1)");
        }
    } else {
        node.expect_object({"translate", "rotate", "scale"});
        mat4 s(1.0f), r(1.0f), tr(1.0f);
        if (auto n = node.find("scale")) {
            vec3 v = n->is_number() ? vec3(n->as_float()) : n->as_vec3();
            s = glm::scale(mat4(1.0f), v);
        }
        if (auto n = node.find("rotate")) {
            if (n->size() != 4) n->fail("must be [angle in degrees, axis x, y, z]");
            float angle = n->at(size_t{0}).as_float();
            vec3 axis(n->at(size_t{1}).as_float(), n->at(size_t{2}).as_float(),
                      n->at(size_t{3}).as_float());
            if (!(glm::length(axis) > 0.0f)) n->fail("rotation axis must be non-zero");
            r = glm::rotate(mat4(1.0f), radians(angle), glm::normalize(axis));
        }
        if (auto n = node.find("translate")) tr = glm::translate(mat4(1.0f), n->as_vec3());
        t.matrix = tr * r * s;  // scale, then rotate, then translate
    }
    float det = glm::determinant(mat3(t.matrix));
    if (!std::isfinite(det) || std::abs(det) < 1e-12f) node.fail("transform is singular");
    t.is_identity = t.matrix == mat4(1.0f);
    return t;
}

namespace {

constexpr int kMaxTreeDepth = 64;  // CSG and SDF nesting: deeper trees are refused

/// One object (not an instance); a mesh file's shared meshes placed into `placed` (where
/// null, as for a CSG child, such a file is refused).
Object parse_object_node(const JsonNode& node, Scene& scene, FileCache& meshes,
                         int inherited_material, int depth, std::vector<Instance>* placed);

/// The children of a CSG node, which must be closed shapes.
Csg parse_csg(const JsonNode& node, Scene& scene, FileCache& meshes, int material, int depth) {
    Csg csg;
    std::string op = node.at("op").as_choice({"union", "intersection", "difference"});
    csg.op = op == "union"          ? CsgOp::Union
             : op == "intersection" ? CsgOp::Intersection
                                    : CsgOp::Difference;
    JsonNode children = node.at("children");
    if (!children.is_array() || children.size() == 0)
        children.fail("must be a non-empty array of objects");
    for (size_t k = 0; k < children.size(); ++k) {
        JsonNode child = children.at(k);
        if (!child.is_object()) child.fail("must be an object");
        std::string type = child.at("type").as_string();
        if (type == "quad" || type == "plane" || type == "implicit") {
            child.at("type").fail(
                "a CSG child must be a closed shape (sphere, box, cylinder, cone, "
                "mesh or csg), not '" +
                type + "'");
        }
        csg.children.push_back(
            parse_object_node(child, scene, meshes, material, depth + 1, nullptr));
    }
    return csg;
}

SdfNode parse_sdf(const JsonNode& node, int depth) {
    if (depth > kMaxTreeDepth)
        node.fail("SDF tree nested deeper than " + std::to_string(kMaxTreeDepth));
    if (!node.is_object()) node.fail("must be an object with an \"op\"");
    SdfNode n;
    std::string op = node.at("op").as_choice({"sphere", "box", "rounded_box", "torus", "cylinder",
                                              "plane", "union", "intersection", "difference"});
    if (auto t = node.find("transform")) n.transform = parse_transform(*t).matrix;
    auto box = [&] {
        n.a = node.at("min").as_vec3();
        n.b = node.at("max").as_vec3();
        if (!(n.a.x < n.b.x && n.a.y < n.b.y && n.a.z < n.b.z))
            node.at("max").fail("must be greater than min on every axis");
    };
    if (op == "sphere") {
        node.expect_object({"op", "center", "radius", "transform"});
        n.op = SdfOp::Sphere;
        n.a = node.at("center").as_vec3();
        n.r1 = node.at("radius").as_positive();
    } else if (op == "box") {
        node.expect_object({"op", "min", "max", "transform"});
        n.op = SdfOp::Box;
        box();
    } else if (op == "rounded_box") {
        node.expect_object({"op", "min", "max", "radius", "transform"});
        n.op = SdfOp::RoundedBox;
        box();
        n.r1 = node.at("radius").as_non_negative();
        if (2.0f * n.r1 > min_component(n.b - n.a))
            node.at("radius").fail("must be at most half the smallest edge");
    } else if (op == "torus") {
        node.expect_object({"op", "center", "major_radius", "minor_radius", "transform"});
        n.op = SdfOp::Torus;
        n.a = node.at("center").as_vec3();
        n.r1 = node.at("major_radius").as_positive();
        n.r2 = node.at("minor_radius").as_positive();
    } else if (op == "cylinder") {
        node.expect_object({"op", "base", "axis", "radius", "transform"});
        n.op = SdfOp::Cylinder;
        n.a = node.at("base").as_vec3();
        n.b = node.at("axis").as_vec3();
        if (!(glm::length(n.b) > 0.0f)) node.at("axis").fail("must be a non-zero vector");
        n.r1 = node.at("radius").as_positive();
    } else if (op == "plane") {
        node.expect_object({"op", "point", "normal", "transform"});
        n.op = SdfOp::Plane;
        n.a = node.at("point").as_vec3();
        n.b = node.at("normal").as_direction();
    } else {
        node.expect_object({"op", "children", "smooth", "transform"});
        n.op = op == "union"          ? SdfOp::Union
               : op == "intersection" ? SdfOp::Intersection
                                      : SdfOp::Difference;
        if (auto k = node.find("smooth")) n.smooth = k->as_non_negative();
        JsonNode children = node.at("children");
        if (!children.is_array() || children.size() == 0)
            children.fail("must be a non-empty array of SDF nodes");
        for (size_t k = 0; k < children.size(); ++k)
            n.children.push_back(parse_sdf(children.at(k), depth + 1));
    }
    return n;
}

Object parse_object_node(const JsonNode& node, Scene& scene, FileCache& meshes,
                         int inherited_material, int depth, std::vector<Instance>* placed) {
    if (!node.is_object()) node.fail("must be an object");
    if (depth > kMaxTreeDepth)
        node.fail("CSG tree nested deeper than " + std::to_string(kMaxTreeDepth));
    std::string type = node.at("type").as_choice({"sphere", "quad", "plane", "box", "cylinder",
                                                  "cone", "mesh", "csg", "implicit", "instance"});
    if (type == "instance") node.fail("an instance belongs in objects or a prototype's objects");
    Object obj;
    obj.name = node.path();
    if (auto t = node.find("transform")) obj.transform = parse_transform(*t);
    obj.material = inherited_material;
    if (auto m = node.find("material")) obj.material = find_material(scene, *m);
    // Meshes may bring their own materials, and a CSG node may leave them to its children.
    else if (type != "mesh" && type != "csg" && obj.material < 0)
        node.at("material");  // fails: missing key
    if (type == "sphere") {
        node.expect_object({"type", "center", "radius", "material", "transform"});
        obj.shape = Sphere{node.at("center").as_vec3(), node.at("radius").as_positive()};
    } else if (type == "quad") {
        node.expect_object({"type", "corner", "edge_u", "edge_v", "material", "transform"});
        Quad q{node.at("corner").as_vec3(), node.at("edge_u").as_vec3(),
               node.at("edge_v").as_vec3()};
        check_non_degenerate_quad(node, q.edge_u, q.edge_v);
        obj.shape = q;
    } else if (type == "plane") {
        node.expect_object({"type", "point", "normal", "material", "transform"});
        obj.shape = Plane{node.at("point").as_vec3(), node.at("normal").as_direction()};
    } else if (type == "box") {
        node.expect_object({"type", "min", "max", "material", "transform"});
        Box b{node.at("min").as_vec3(), node.at("max").as_vec3()};
        if (!(b.min.x < b.max.x && b.min.y < b.max.y && b.min.z < b.max.z)) {
            node.at("max").fail("must be greater than min on every axis");
        }
        obj.shape = b;
    } else if (type == "cylinder" || type == "cone") {
        node.expect_object({"type", "base", "axis", "radius", "material", "transform"});
        vec3 base = node.at("base").as_vec3();
        vec3 axis = node.at("axis").as_vec3();
        if (!(glm::length(axis) > 0.0f)) node.at("axis").fail("must be a non-zero vector");
        float radius = node.at("radius").as_positive();
        if (type == "cylinder")
            obj.shape = Cylinder{base, axis, radius};
        else
            obj.shape = Cone{base, axis, radius};
    } else if (type == "mesh") {
        node.expect_object({"type", "file", "positions", "indices", "normals", "uvs", "smooth",
                            "material", "transform"});
        std::vector<SharedPlaces> shared;
        obj.shape = parse_mesh(node, scene, meshes, obj.material, obj.transform,
                               placed ? &shared : nullptr);
        for (const SharedPlaces& s : shared) {
            for (const mat4& place : s.places) {
                Instance i;
                i.name = node.path();
                i.prototype = s.prototype;
                i.transform.matrix = obj.transform.matrix * place;
                i.transform.is_identity = false;
                placed->push_back(std::move(i));
            }
        }
    } else if (type == "csg") {
        node.expect_object({"type", "op", "children", "material", "transform"});
        obj.shape = parse_csg(node, scene, meshes, obj.material, depth);
    } else {
        node.expect_object({"type", "sdf", "material", "transform"});
        obj.shape = Implicit{parse_sdf(node.at("sdf"), 1)};
    }
    return obj;
}

}  // namespace

namespace {

/// Bounds on what instances make (docs/scene-format.md, "Instances"): placements, and the
/// triangles of the instances written out as copies.
constexpr size_t kMaxInstances = size_t{1} << 20;

/// Whether `prototype` placed with material `material` (-1: its own) must be written out:
/// it holds an emitter (the light set samples emitters in world space), an infinite plane or
/// an implicit surface (which may be unbounded: no box would hold it).
bool needs_copies(const Scene& scene, const Prototype& prototype, int material) {
    const auto emitting = [&](int m) {
        return m >= 0 && emits(scene.materials[static_cast<size_t>(m)]);
    };
    if (emitting(material)) return true;
    for (const Object& o : prototype.objects) {
        if (std::holds_alternative<Plane>(o.shape) || std::holds_alternative<Implicit>(o.shape))
            return true;
        if (material >= 0) continue;
        const auto* mesh = std::get_if<Mesh>(&o.shape);
        if (mesh && o.material < 0
                ? std::any_of(mesh->face_material.begin(), mesh->face_material.end(), emitting)
                : emitting(o.material))
            return true;
    }
    return false;
}

}  // namespace

Prototypes::Prototypes(std::optional<JsonNode> section) : section_(std::move(section)) {
    if (!section_) return;
    if (!section_->is_object()) section_->fail("must be an object of prototypes by name");
    for (const auto& item : section_->raw().items()) {
        const JsonNode p = section_->at(item.key());
        if (!p.is_object()) p.fail("expected {\"objects\": [...]}");
        p.expect_object({"objects"});
        if (!p.at("objects").is_array()) p.at("objects").fail("must be an array of objects");
    }
}

const Prototypes::Parts& Prototypes::get(const JsonNode& name_node, Scene& scene,
                                         FileCache& meshes) {
    const std::string name = name_node.as_string();
    if (auto it = parsed_.find(name); it != parsed_.end()) return it->second;
    if (!section_ || !section_->has(name)) {
        std::string known;
        if (section_)
            for (const auto& [key, value] : section_->raw().items())
                known += (known.empty() ? "" : ", ") + key;
        name_node.fail(
            "unknown prototype '" + name + "'" +
            (known.empty() ? " (the scene has no prototypes)" : " (the scene has: " + known + ")"));
    }
    if (std::find(expanding_.begin(), expanding_.end(), name) != expanding_.end()) {
        std::string chain;
        for (const std::string& p : expanding_) chain += p + " -> ";
        name_node.fail("prototype '" + name + "' holds an instance of itself (" + chain + name +
                       ")");
    }
    expanding_.push_back(name);
    std::vector<Object> own;
    std::vector<Instance> nested;
    const size_t lights_before = scene.lights.size();
    const JsonNode objects = section_->at(name).at("objects");
    for (size_t k = 0; k < objects.size(); ++k)
        parse_object(objects.at(k), scene, meshes, *this, own, nested);
    Parts parts;
    if (!own.empty()) {
        scene.prototypes.push_back({name, std::move(own)});
        Instance self;
        self.prototype = static_cast<uint32_t>(scene.prototypes.size() - 1);
        parts.placements.push_back(self);
    }
    parts.placements.insert(parts.placements.end(), nested.begin(), nested.end());
    parts.lights.assign(scene.lights.begin() + static_cast<std::ptrdiff_t>(lights_before),
                        scene.lights.end());
    scene.lights.resize(lights_before);
    expanding_.pop_back();
    return parsed_.emplace(name, std::move(parts)).first->second;
}

void parse_object(const JsonNode& node, Scene& scene, FileCache& meshes, Prototypes& prototypes,
                  std::vector<Object>& out, std::vector<Instance>& placed) {
    if (!node.is_object() || !node.has("type") || !node.at("type").is_string() ||
        node.at("type").as_string() != "instance") {
        Object obj = parse_object_node(node, scene, meshes, -1, 1, &placed);
        // (A mesh file whose every mesh is shared leaves nothing of its own.)
        const auto* mesh = std::get_if<Mesh>(&obj.shape);
        if (!mesh || !mesh->indices.empty()) out.push_back(std::move(obj));
        return;
    }
    node.expect_object({"type", "prototype", "transform", "material"});
    Transform place;
    if (auto t = node.find("transform")) place = parse_transform(*t);
    int material = -1;
    if (auto m = node.find("material")) material = find_material(scene, *m);
    const Prototypes::Parts& parts = prototypes.get(node.at("prototype"), scene, meshes);
    for (const Instance& p : parts.placements) {
        if (++prototypes.placed > kMaxInstances)
            node.fail("the instances would place more than " + std::to_string(kMaxInstances) +
                      " prototypes");
        Instance i;
        i.name = node.path();
        i.prototype = p.prototype;
        i.transform.matrix = place.matrix * p.transform.matrix;
        i.transform.is_identity = place.is_identity && p.transform.is_identity;
        i.material = material >= 0 ? material : p.material;
        placed.push_back(std::move(i));
    }
    for (const Light& l : parts.lights) scene.lights.push_back(transformed(l, place));
}

void settle_instances(std::vector<Instance> placed, Scene& scene) {
    uint64_t copied_triangles = 0;
    for (Instance& i : placed) {
        const Prototype& prototype = scene.prototypes[i.prototype];
        if (!needs_copies(scene, prototype, i.material)) {
            scene.instances.push_back(std::move(i));
            continue;
        }
        for (const Object& o : prototype.objects) {
            copied_triangles += object_triangles(o);
            if (copied_triangles > kMaxCopiedTriangles)
                throw Error(scene.path.string(), i.name,
                            "the instances written out as copies (those that emit or hold a "
                            "plane) would make more than " +
                                std::to_string(kMaxCopiedTriangles) + " triangles");
            scene.objects.push_back(placed_object(o, i));
            scene.copied_objects += 1;
        }
    }
}

}  // namespace svetlo
