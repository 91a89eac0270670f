#include "svetlo/scene/gltf_flatten.h"

#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>

#include "svetlo/scene/gltf_accessors.h"
#include "svetlo/scene/gltf_nodes.h"

namespace svetlo {

namespace {

/// The most placements EXT_mesh_gpu_instancing may make in one file (as many as a scene's
/// `instance` objects may: docs/scene-format.md, "Instances").
constexpr size_t kMaxGpuInstances = size_t{1} << 20;

struct Flattener {
    const tinygltf::Model& model;
    MeshFile& file;
    int depth_guard = 0;
    std::set<int> colored_materials;  // the materials of primitives with COLOR_0
    Mesh* target = &file.mesh;        // the mesh add_mesh appends to
    std::vector<mat4> node_world{};   // every node's transform to the file's world
    /// A node's mesh, its place in the file, its morph targets' weights and its skin.
    struct Use {
        int mesh;
        mat4 world;
        const std::vector<double>* weights;
        bool own_weights;  // the node's weights, not the mesh's
        int skin = -1;     // placed by the skin's joints (gltf_nodes.h), the node's place ignored
    };
    std::vector<Use> uses{};

    /// The meshes the nodes visited place: baked into file.mesh where one node places a
    /// mesh (or gives it weights of its own, or a transform without an inverse: a scale of
    /// zero along an axis), kept in their own space (MeshFile::shared) where several do.
    void place_meshes() {
        const auto instanced = [](const Use& use) {
            const float det = glm::determinant(mat3(use.world));
            return !use.own_weights && use.skin < 0 && std::isfinite(det) &&
                   std::abs(det) >= 1e-12f;
        };
        std::map<int, int> count, shared;  // per mesh index: its nodes; its MeshFile::shared
        for (const Use& use : uses)
            if (instanced(use)) ++count[use.mesh];
        for (const Use& use : uses) {
            if (!instanced(use) || count[use.mesh] < 2) {
                add_mesh(use.mesh, use.world, *use.weights, use.skin);
                continue;
            }
            auto [at, made] = shared.try_emplace(use.mesh, static_cast<int>(file.shared.size()));
            if (made) {
                file.shared.emplace_back();
                target = &file.shared.back().mesh;
                add_mesh(use.mesh, mat4(1.0f), *use.weights, -1);
                target = &file.mesh;
            }
            file.shared[static_cast<size_t>(at->second)].places.push_back(use.world);
        }
    }

    /// Mesh::uvs1 up to vertex `end`: set 0's coordinates (or zero) where a vertex has no
    /// second set.
    void fill_second_set(size_t end) {
        Mesh& mesh = *target;
        for (size_t v = mesh.uvs1.size(); v < end; ++v)
            mesh.uvs1.push_back(v < mesh.uvs.size() ? mesh.uvs[v] : vec2(0.0f));
    }

    void visit(int node_index, const mat4& parent) {
        if (node_index < 0 || static_cast<size_t>(node_index) >= model.nodes.size()) {
            throw std::runtime_error("node " + std::to_string(node_index) + " missing");
        }
        if (++depth_guard > 10000) throw std::runtime_error("node hierarchy too deep or cyclic");
        const tinygltf::Node& node = model.nodes[node_index];
        mat4 world = parent * node_matrix(node);
        if (node.mesh >= 0) {
            if (static_cast<size_t>(node.mesh) >= model.meshes.size())
                throw std::runtime_error("mesh " + std::to_string(node.mesh) + " missing");
            const std::vector<double>& defaults =
                model.meshes[static_cast<size_t>(node.mesh)].weights;
            const bool own = !node.weights.empty() && node.weights != defaults;
            const auto gpu = node.extensions.find("EXT_mesh_gpu_instancing");
            if (gpu != node.extensions.end() && gpu->second.Has("attributes")) {
                for (const mat4& local : gpu_instances(gpu->second.Get("attributes"), node_index))
                    uses.push_back(
                        {node.mesh, world * local, own ? &node.weights : &defaults, own});
            } else {
                uses.push_back({node.mesh, world, own ? &node.weights : &defaults, own, node.skin});
            }
        }
        add_light(node, world);
        if (node.camera >= 0 && !file.camera) add_camera(node.camera, world);
        for (int child : node.children) visit(child, world);
        --depth_guard;
    }

    size_t gpu_placed = 0;  // the placements EXT_mesh_gpu_instancing made so far

    /// EXT_mesh_gpu_instancing's placements of node `node_index`'s mesh, within the node's
    /// space: one a element of its TRANSLATION (VEC3), ROTATION (VEC4, a unit quaternion
    /// x, y, z, w; float or normalised) and SCALE (VEC3) accessors, each T R S, as a node's own
    /// transform; an attribute not given is the identity's.
    std::vector<mat4> gpu_instances(const tinygltf::Value& attributes, int node_index) {
        const std::string name = "node " + std::to_string(node_index) + " EXT_mesh_gpu_instancing";
        std::optional<AccessorView> t, r, s;
        const auto view = [&](const char* key, int components, std::optional<AccessorView>& out) {
            if (!attributes.Has(key)) return;
            const tinygltf::Value& v = attributes.Get(key);
            if (!v.IsInt() && !v.IsNumber()) throw std::runtime_error(name + ": " + key);
            out.emplace(model, v.GetNumberAsInt(), components);
        };
        view("TRANSLATION", 3, t);
        view("ROTATION", 4, r);
        view("SCALE", 3, s);
        size_t count = 0;
        for (const auto* a : {&t, &r, &s})
            if (*a) {
                if (count != 0 && (*a)->count() != count)
                    throw std::runtime_error(name + ": its attributes' counts differ");
                count = (*a)->count();
            }
        gpu_placed += count;
        if (gpu_placed > kMaxGpuInstances)
            throw std::runtime_error(name + ": more than " + std::to_string(kMaxGpuInstances) +
                                     " instances in the file");
        std::vector<mat4> out(count, mat4(1.0f));
        for (size_t k = 0; k < count; ++k) {
            mat4 m(1.0f);
            if (t)
                m = glm::translate(
                    m, vec3(t->component(k, 0), t->component(k, 1), t->component(k, 2)));
            if (r) {
                const std::optional<mat4> turn = unit_rotation(
                    r->component(k, 0), r->component(k, 1), r->component(k, 2), r->component(k, 3));
                if (!turn)
                    throw std::runtime_error(name + ": rotation " + std::to_string(k) +
                                             " is not a quaternion");
                m = m * *turn;
            }
            if (s)
                m = glm::scale(m, vec3(s->component(k, 0), s->component(k, 1), s->component(k, 2)));
            out[k] = m;
        }
        return out;
    }

    /// glTF's camera looks down its node's -z with +y up (glTF 2.0, 3.10); yfov is the full
    /// vertical angle in radians, ymag half the orthographic film's height.
    void add_camera(int index, const mat4& world) {
        if (static_cast<size_t>(index) >= model.cameras.size())
            throw std::runtime_error("camera " + std::to_string(index) + " missing");
        const tinygltf::Camera& c = model.cameras[static_cast<size_t>(index)];
        Camera camera;
        camera.position = vec3(world * vec4(0.0f, 0.0f, 0.0f, 1.0f));
        const vec3 forward = vec3(world * vec4(0.0f, 0.0f, -1.0f, 0.0f));
        camera.up = vec3(world * vec4(0.0f, 1.0f, 0.0f, 0.0f));
        if (!(glm::length(forward) > 0.0f) || !(glm::length(camera.up) > 0.0f))
            throw std::runtime_error("camera " + std::to_string(index) + ": a degenerate node");
        camera.look_at = camera.position + glm::normalize(forward);
        if (c.type == "orthographic") {
            camera.type = Camera::Type::Orthographic;
            camera.height = static_cast<float>(2.0 * c.orthographic.ymag);
            if (!(camera.height > 0.0f))
                throw std::runtime_error("camera " + std::to_string(index) + ": ymag must be > 0");
        } else {
            camera.fov_deg = static_cast<float>(c.perspective.yfov * 180.0 / M_PI);
            if (!(camera.fov_deg > 0.0f && camera.fov_deg < 180.0f))
                throw std::runtime_error("camera " + std::to_string(index) + ": yfov out of range");
        }
        file.camera = camera;
    }

    void add_light(const tinygltf::Node& node, const mat4& world) {
        auto ext = node.extensions.find("KHR_lights_punctual");
        if (ext == node.extensions.end() || !ext->second.Has("light")) return;
        int index = ext->second.Get("light").GetNumberAsInt();
        if (index < 0 || static_cast<size_t>(index) >= model.lights.size()) {
            throw std::runtime_error("light " + std::to_string(index) + " missing");
        }
        const tinygltf::Light& l = model.lights[index];
        double r = 1.0, g = 1.0, b = 1.0;
        if (l.color.size() == 3) {
            r = l.color[0];
            g = l.color[1];
            b = l.color[2];
        }
        Color c = file_color(r * l.intensity, g * l.intensity, b * l.intensity,
                             "light " + std::to_string(index) + " color times intensity");
        vec3 position = vec3(world * vec4(0.0f, 0.0f, 0.0f, 1.0f));
        vec3 direction = glm::normalize(vec3(world * vec4(0.0f, 0.0f, -1.0f, 0.0f)));
        if (l.type == "point") {
            file.lights.push_back(PointLight{position, c});
        } else if (l.type == "directional") {
            file.lights.push_back(DirectionalLight{direction, c});
        } else if (l.type == "spot") {
            SpotLight s;
            s.position = position;
            s.direction = direction;
            s.intensity = c;
            s.inner_deg = static_cast<float>(l.spot.innerConeAngle * 180.0 / M_PI);
            s.outer_deg = static_cast<float>(l.spot.outerConeAngle * 180.0 / M_PI);
            file.lights.push_back(s);
        } else {
            throw std::runtime_error("unknown light type '" + l.type + "'");
        }
    }

    /// Texture coordinate set `name` of `prim` (one per position), empty when it has none;
    /// glTF's v runs down the image, svetlo's (OpenGL's) up.
    std::vector<vec2> texture_coordinates(const tinygltf::Primitive& prim, const char* name,
                                          size_t count) const {
        std::vector<vec2> out;
        auto it = prim.attributes.find(name);
        if (it == prim.attributes.end()) return out;
        AccessorView uvs(model, it->second, 2);
        if (uvs.count() != count) throw std::runtime_error(std::string(name) + " count");
        for (size_t k = 0; k < uvs.count(); ++k)
            out.emplace_back(uvs.component(k, 0), 1.0 - uvs.component(k, 1));
        return out;
    }

    /// COLOR_0 of `prim`, its `count` vertices from `base` on (VEC3 or VEC4; floats, or
    /// normalised unsigned bytes or shorts; linear, each component in [0, 1]).
    void add_vertex_colors(const tinygltf::Primitive& prim, size_t count, size_t base) {
        auto col = prim.attributes.find("COLOR_0");
        if (col == prim.attributes.end()) return;
        const int n = AccessorView::components_of(model, col->second) == 4 ? 4 : 3;
        AccessorView colors(model, col->second, n);
        if (colors.count() != count) throw std::runtime_error("COLOR_0 count");
        Mesh& mesh = *target;
        mesh.colors.resize(base, vec4(1.0f));
        for (size_t k = 0; k < colors.count(); ++k) {
            vec4 c(1.0f);
            for (int i = 0; i < n; ++i) {
                const double x = colors.component(k, i);
                if (!std::isfinite(x) || x < 0.0 || x > 1.0)
                    throw std::runtime_error("COLOR_0 " + std::to_string(k) +
                                             " lies outside [0, 1]");
                c[i] = static_cast<float>(x);
            }
            mesh.colors.push_back(c);
        }
        if (prim.material >= 0) colored_materials.insert(prim.material);
    }

    /// The sum over `prim`'s morph targets of weight times the target's `attribute` (glTF
    /// 2.0, 3.7.2.2), one per vertex; empty where no target with a weight moves it.
    std::vector<vec3> morph_offsets(const tinygltf::Primitive& prim,
                                    const std::vector<double>& weights, const char* attribute,
                                    size_t count) const {
        std::vector<vec3> out;
        for (size_t i = 0; i < prim.targets.size() && i < weights.size(); ++i) {
            const auto it = prim.targets[i].find(attribute);
            if (it == prim.targets[i].end() || weights[i] == 0.0) continue;
            if (!std::isfinite(weights[i])) throw std::runtime_error("morph weight not finite");
            AccessorView offsets(model, it->second, 3);
            if (offsets.count() != count)
                throw std::runtime_error(std::string("morph target ") + attribute + " count");
            out.resize(count, vec3(0.0f));
            for (size_t k = 0; k < count; ++k)
                out[k] +=
                    static_cast<float>(weights[i]) *
                    vec3(offsets.component(k, 0), offsets.component(k, 1), offsets.component(k, 2));
        }
        return out;
    }

    /// NORMAL and TANGENT of `prim` (moved by its morph targets' `weights`), its `count`
    /// vertices from `base` on, into world space. A primitive without NORMAL is flat (glTF
    /// 2.0, 3.7.2.1): its vertices' normals are zero, which every engine reads as the
    /// triangle's own.
    void add_normals_and_tangents(const tinygltf::Primitive& prim, size_t count, size_t base,
                                  const mat4& world, const std::vector<double>& weights,
                                  const std::vector<mat4>& skinned) {
        Mesh& mesh = *target;
        const mat3 nm = normal_matrix(world);
        const auto at = [&](size_t k) { return skinned.empty() ? world : skinned[k]; };
        mesh.normals.resize(base, vec3(0.0f));
        auto nor = prim.attributes.find("NORMAL");
        if (nor != prim.attributes.end()) {
            AccessorView normals(model, nor->second, 3);
            if (normals.count() != count) throw std::runtime_error("NORMAL count");
            const std::vector<vec3> moved = morph_offsets(prim, weights, "NORMAL", count);
            for (size_t k = 0; k < normals.count(); ++k) {
                vec3 n(normals.component(k, 0), normals.component(k, 1), normals.component(k, 2));
                if (!moved.empty()) n += moved[k];
                n = skinned.empty() ? nm * n : normal_matrix(skinned[k]) * n;
                const float len = glm::length(n);
                mesh.normals.push_back(len > 0.0f && std::isfinite(len) ? n / len : vec3(0.0f));
            }
        } else {
            mesh.normals.resize(base + count, vec3(0.0f));
        }
        auto tan = prim.attributes.find("TANGENT");
        if (tan != prim.attributes.end()) {
            AccessorView tangents(model, tan->second, 4);
            if (tangents.count() != count) throw std::runtime_error("TANGENT count");
            const std::vector<vec3> moved = morph_offsets(prim, weights, "TANGENT", count);
            mesh.tangents.resize(base);
            for (size_t k = 0; k < tangents.count(); ++k) {
                // glTF's v runs down the image and svetlo's up, but glTF's bitangent
                // (w cross(n, t)) is the map's +y, up the image: the sign stays.
                vec4 t(tangents.component(k, 0), tangents.component(k, 1), tangents.component(k, 2),
                       tangents.component(k, 3));
                if (!moved.empty()) t += vec4(moved[k], 0.0f);
                mesh.tangents.push_back(transform_tangent(Transform{at(k), false}, t));
            }
        }
    }

    /// The triangles of `prim`, whose `count` vertices start at `base`: its vertices (its
    /// indices, or the vertices in order) as a list, a strip or a fan (glTF 2.0, 3.7.2.1:
    /// strip triangle i is v_i, v_(i + 1 + i % 2), v_(i + 2 - i % 2); fan triangle i is
    /// v_(i + 1), v_(i + 2), v_0).
    void add_indices(const tinygltf::Primitive& prim, size_t count, uint32_t base) {
        std::vector<uint32_t> v;
        if (prim.indices >= 0) {
            AccessorView indices(model, prim.indices, 1);
            v.reserve(indices.count());
            for (size_t k = 0; k < indices.count(); ++k) {
                double i = indices.component(k, 0);
                if (i < 0 || i >= static_cast<double>(count)) {
                    throw std::runtime_error("index out of range");
                }
                v.push_back(base + static_cast<uint32_t>(i));
            }
        } else {
            v.resize(count);
            for (size_t k = 0; k < count; ++k) v[k] = base + static_cast<uint32_t>(k);
        }
        std::vector<uint32_t>& out = target->indices;
        if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            for (size_t i = 0; i + 2 < v.size(); ++i)
                out.insert(out.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
        } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
            for (size_t i = 0; i + 2 < v.size(); ++i)
                out.insert(out.end(), {v[i + 1], v[i + 2], v[0]});
        } else {
            if (v.size() % 3 != 0) throw std::runtime_error("index count");
            out.insert(out.end(), v.begin(), v.end());
        }
    }

    static bool is_triangles(const tinygltf::Primitive& prim) {
        return prim.mode == -1 || prim.mode == TINYGLTF_MODE_TRIANGLES ||
               prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
    }

    /// Mesh `mesh_index`'s triangle primitives, their morph targets moved by `weights`,
    /// placed by `world`, or by skin `skin`'s joints where it is one (>= 0) and the
    /// primitive has JOINTS_0.
    void add_mesh(int mesh_index, const mat4& world, const std::vector<double>& weights, int skin) {
        if (static_cast<size_t>(mesh_index) >= model.meshes.size()) {
            throw std::runtime_error("mesh " + std::to_string(mesh_index) + " missing");
        }
        Mesh& mesh = *target;
        for (const tinygltf::Primitive& prim : model.meshes[mesh_index].primitives) {
            if (!is_triangles(prim)) continue;
            auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end())
                throw std::runtime_error("primitive without POSITION");
            AccessorView positions(model, pos->second, 3);
            auto base = static_cast<uint32_t>(mesh.positions.size());
            const std::vector<vec3> moved =
                morph_offsets(prim, weights, "POSITION", positions.count());
            const std::vector<mat4> skinned =
                skin >= 0 ? skinning_matrices(model, skin, prim, positions.count(), node_world)
                          : std::vector<mat4>{};
            for (size_t k = 0; k < positions.count(); ++k) {
                vec3 p(positions.component(k, 0), positions.component(k, 1),
                       positions.component(k, 2));
                if (!moved.empty()) p += moved[k];
                mesh.positions.push_back(
                    vec3((skinned.empty() ? world : skinned[k]) * vec4(p, 1.0f)));
            }
            add_normals_and_tangents(prim, positions.count(), base, world, weights, skinned);
            if (std::vector<vec2> uvs = texture_coordinates(prim, "TEXCOORD_0", positions.count());
                !uvs.empty()) {
                mesh.uvs.resize(base);
                mesh.uvs.insert(mesh.uvs.end(), uvs.begin(), uvs.end());
            }
            if (std::vector<vec2> uvs = texture_coordinates(prim, "TEXCOORD_1", positions.count());
                !uvs.empty()) {
                fill_second_set(base);
                mesh.uvs1.insert(mesh.uvs1.end(), uvs.begin(), uvs.end());
            }
            add_vertex_colors(prim, positions.count(), base);
            // A primitive without a second set reads its first there; one without colours
            // is white.
            if (!mesh.uvs1.empty()) fill_second_set(mesh.positions.size());
            if (!mesh.colors.empty()) mesh.colors.resize(mesh.positions.size(), vec4(1.0f));
            add_indices(prim, positions.count(), base);
            int material =
                prim.material >= 0 && static_cast<size_t>(prim.material) < file.materials.size()
                    ? prim.material
                    : -1;
            mesh.face_material.resize(mesh.indices.size() / 3, material);
        }
    }
};

}  // namespace

void place_gltf_nodes(const tinygltf::Model& model, MeshFile& file) {
    Flattener flattener{model, file, 0, {}};
    flattener.node_world = node_world_matrices(model);  // also checks that the nodes are trees
    int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (static_cast<size_t>(scene) < model.scenes.size()) {
        for (int node : model.scenes[scene].nodes) flattener.visit(node, mat4(1.0f));
    } else {  // no scene: every tree of nodes, from its root
        std::vector<char> child(model.nodes.size(), 0);
        for (const tinygltf::Node& node : model.nodes)
            for (int c : node.children) child[static_cast<size_t>(c)] = 1;
        for (size_t n = 0; n < model.nodes.size(); ++n)
            if (!child[n]) flattener.visit(static_cast<int>(n), mat4(1.0f));
    }
    flattener.place_meshes();
    // COLOR_0 multiplies the base colour and its alpha (glTF 2.0, 3.9.2), in the materials of
    // the primitives that have it (another primitive of such a material is white).
    for (int m : flattener.colored_materials) {
        if (static_cast<size_t>(m) >= file.materials.size()) continue;
        Material& material = file.materials[static_cast<size_t>(m)];
        if (auto* ct = std::get_if<CookTorranceMaterial>(&material.model))
            ct->base_color.vertex_color = VertexColor::Rgb;
        else  // KHR_materials_unlit: its base colour is its emission (gltf_materials.cpp)
            material.emission.vertex_color = VertexColor::Rgb;
        if (material.alpha.active()) material.alpha.coverage.vertex_color = VertexColor::Alpha;
    }
    if (file.mesh.indices.empty() && file.shared.empty())
        throw std::runtime_error("glTF file has no triangles");
    const auto finish = [&](Mesh& mesh) {
        if (!mesh.normals.empty()) mesh.normals.resize(mesh.positions.size(), vec3(0.0f));
        if (!mesh.uvs.empty()) mesh.uvs.resize(mesh.positions.size(), vec2(0.0f));
        flattener.target = &mesh;
        if (!mesh.uvs1.empty()) flattener.fill_second_set(mesh.positions.size());
        if (!mesh.colors.empty()) mesh.colors.resize(mesh.positions.size(), vec4(1.0f));
        if (!mesh.tangents.empty()) mesh.tangents.resize(mesh.positions.size(), vec4(0.0f));
        bool any_material = false;
        for (int m : mesh.face_material) any_material = any_material || m >= 0;
        if (!any_material) mesh.face_material.clear();
    };
    finish(file.mesh);
    for (MeshFile::Shared& s : file.shared) finish(s.mesh);
}

}  // namespace svetlo
