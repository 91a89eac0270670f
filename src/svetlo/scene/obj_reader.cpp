// OBJ and MTL through tinyobjloader. Every (position, normal, uv) triple becomes one vertex,
// so seams keep their own normals and texture coordinates. MTL mapping (docs/scene-format.md,
// "OBJ/MTL"): Ke > 0 or map_Ke -> emissive (Kd or map_Kd as albedo); illum 3 or 5 -> mirror
// (Ks); illum 4, 6, 7 or d < 1 -> dielectric (Ni); Pr or Pm > 0 -> cook_torrance; otherwise
// phong with Ka, Kd or map_Kd, Ks or map_Ks, Ns times map_Ns; map_Pr and map_Pm make
// cook_torrance's metallic_roughness. `norm` is a tangent-space normal map,
// `map_Bump` (or `bump`) a height map made into one.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>
#include <tuple>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/input_file.h"
#include "svetlo/scene/mesh_file.h"

namespace svetlo {

namespace {

/// The texture maps an MTL names (map_Kd, map_Ks, map_Ke), each read once per colour space
/// into the file's textures, inside the file scope, relative to the OBJ's folder.
class MtlTextures {
public:
    MtlTextures(std::filesystem::path dir, const FileScope& files, MeshFile& file)
        : dir_(std::move(dir)), files_(files), file_(file) {}

    /// `constant` when `name` is empty, else the texture times `factor`.
    ColorSource source(const std::string& name, Color constant, Color factor, TexelMeaning meaning,
                       const std::string& what) {
        if (name.empty()) return ColorSource::constant(constant);
        const std::filesystem::path path = files_.resolve(dir_, name);
        const std::string key =
            path.lexically_normal().string() + " " + std::to_string(static_cast<int>(meaning));
        ColorSource s;
        s.kind = ColorSource::Kind::Image;
        s.factor = factor;
        if (auto known = made_.find(key); known != made_.end()) {
            s.texture = known->second;
            return s;
        }
        try {
            file_.textures.push_back(read_texture(path, meaning, kMaxTextureBytes, what));
        } catch (const Error& e) {
            throw std::runtime_error(what + " '" + name + "': " + e.message());
        }
        s.texture = made_[key] = static_cast<int>(file_.textures.size()) - 1;
        return s;
    }

    /// The tangent-space normal map of height map `name` (map_Bump, bump): at each texel the
    /// normal (-bm dh/di, -bm dh/dj, 1), normalised, the heights' central differences across
    /// one texel (i to the right, j up the image), h read linear in [0, 1] (its first channel)
    /// times the MTL's -bm. Kept as float texels in the map's encoding, (n + 1) / 2.
    ColorSource height_map(const std::string& name, float bm, const std::string& what) {
        ColorSource heights = source(name, Color(0.0f), Color(1.0f), TexelMeaning::Linear, what);
        const TextureImage& h = file_.textures[static_cast<size_t>(heights.texture)];
        const int w = h.width(), ht = h.height();
        Image normals(w, ht);
        for (int j = 0; j < ht; ++j)
            for (int i = 0; i < w; ++i) {
                // Rows from the top: up the image is j - 1. Repeated across the edges.
                const float dh_di =
                    0.5f * (h.texel((i + 1) % w, j).r - h.texel((i + w - 1) % w, j).r);
                const float dh_dj =
                    0.5f * (h.texel(i, (j + ht - 1) % ht).r - h.texel(i, (j + 1) % ht).r);
                const vec3 n = glm::normalize(vec3(-bm * dh_di, -bm * dh_dj, 1.0f));
                normals.at(i, j) = 0.5f * (n + vec3(1.0f));
            }
        file_.textures.emplace_back(std::move(normals));
        heights.texture = static_cast<int>(file_.textures.size()) - 1;
        return heights;
    }

    /// glTF's metallic-roughness texture (G roughness, B metallic) from the MTL's scalar maps
    /// map_Pr and map_Pm (either may be empty: its channel is then 1, the factor alone), each
    /// read linear, its first channel; at the larger map's size, the other read nearest.
    ColorSource metallic_roughness(const std::string& pr, const std::string& pm,
                                   const std::string& what) {
        const ColorSource r =
            source(pr, Color(1.0f), Color(1.0f), TexelMeaning::Linear, what + "map_Pr");
        const ColorSource m =
            source(pm, Color(1.0f), Color(1.0f), TexelMeaning::Linear, what + "map_Pm");
        const TextureImage* maps[2] = {
            r.texture >= 0 ? &file_.textures[static_cast<size_t>(r.texture)] : nullptr,
            m.texture >= 0 ? &file_.textures[static_cast<size_t>(m.texture)] : nullptr};
        int w = 1, h = 1;
        for (const TextureImage* t : maps)
            if (t && t->width() * t->height() > w * h) w = t->width(), h = t->height();
        Image both(w, h, Color(0.0f, 1.0f, 1.0f));
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i)
                for (int k = 0; k < 2; ++k) {
                    const TextureImage* t = maps[k];
                    if (!t) continue;
                    both.at(i, j)[k + 1] = t->texel(i * t->width() / w, j * t->height() / h).r;
                }
        file_.textures.emplace_back(std::move(both));
        ColorSource s;
        s.kind = ColorSource::Kind::Image;
        s.texture = static_cast<int>(file_.textures.size()) - 1;
        return s;
    }

private:
    std::filesystem::path dir_;
    const FileScope& files_;
    MeshFile& file_;
    std::map<std::string, int> made_;
};

MaterialModel model_from_mtl(const tinyobj::material_t& m, MtlTextures& textures) {
    // Every colour of the MTL checked (file_color): 'Kd 1e39' or 'Kd -1 0.5 0.5' is refused.
    auto color = [&](const tinyobj::real_t c[3], const char* key) {
        return file_color(c[0], c[1], c[2], "material '" + m.name + "' " + key);
    };
    const Color ke = color(m.emission, "Ke"), kd = color(m.diffuse, "Kd"),
                ks = color(m.specular, "Ks"), ka = color(m.ambient, "Ka");
    if (!std::isfinite(m.shininess) || !std::isfinite(m.ior) || !std::isfinite(m.dissolve)) {
        throw std::runtime_error("material '" + m.name + "': Ns, Ni and d must be finite");
    }
    // A map replaces its colour (as Blender's importer reads it); map_Ke is scaled by Ke
    // (by 1 where Ke is black).
    const std::string name = "material '" + m.name + "' ";
    const ColorSource diffuse =
        textures.source(m.diffuse_texname, kd, Color(1.0f), TexelMeaning::Srgb, name + "map_Kd");
    const ColorSource specular =
        textures.source(m.specular_texname, ks, Color(1.0f), TexelMeaning::Srgb, name + "map_Ks");
    if (max_component(ke) > 0.0f || !m.emissive_texname.empty()) {
        EmissiveMaterial e;
        e.radiance =
            textures.source(m.emissive_texname, ke, max_component(ke) > 0.0f ? ke : Color(1.0f),
                            TexelMeaning::Srgb, name + "map_Ke");
        e.albedo = diffuse;
        return e;
    }
    if (m.illum == 3 || m.illum == 5) {
        MirrorMaterial mirror;
        mirror.reflectance = ColorSource::constant(ks);
        return mirror;
    }
    if (m.illum == 4 || m.illum == 6 || m.illum == 7 ||
        (m.dissolve < 1.0f && m.alpha_texname.empty())) {
        DielectricMaterial d;
        d.ior = m.ior > 1.0f ? m.ior : 1.5f;
        return d;
    }
    const bool pbr_maps = !m.roughness_texname.empty() || !m.metallic_texname.empty();
    if (m.roughness > 0.0f || m.metallic > 0.0f || pbr_maps) {  // the PBR extension
        CookTorranceMaterial ct;
        ct.base_color = diffuse;
        // A map replaces its value, as map_Kd replaces Kd.
        ct.roughness = m.roughness_texname.empty()
                           ? std::clamp(static_cast<float>(m.roughness), 0.0f, 1.0f)
                           : 1.0f;
        ct.metallic = m.metallic_texname.empty()
                          ? std::clamp(static_cast<float>(m.metallic), 0.0f, 1.0f)
                          : 1.0f;
        if (pbr_maps)
            ct.metallic_roughness =
                textures.metallic_roughness(m.roughness_texname, m.metallic_texname, name);
        return ct;
    }
    PhongMaterial p;
    p.ka = ColorSource::constant(ka);
    p.kd = diffuse;
    p.ks = specular;
    p.shininess = m.shininess > 0.0f ? m.shininess : 1.0f;
    // map_Ns: a scalar map multiplying Ns (the MTL specification), its first channel, linear.
    p.shininess_map = textures.source(m.specular_highlight_texname, Color(1.0f), Color(1.0f),
                                      TexelMeaning::Linear, name + "map_Ns");
    return p;
}

/// The material an MTL entry describes: its model and its normal map (norm, else map_Bump or
/// bump as a height map).
Material material_from_mtl(const tinyobj::material_t& m, MtlTextures& textures) {
    Material out = model_from_mtl(m, textures);
    const std::string name = "material '" + m.name + "' ";
    if (!m.normal_texname.empty()) {
        out.normal_map.texture = textures.source(m.normal_texname, Color(0.0f), Color(1.0f),
                                                 TexelMeaning::Linear, name + "norm");
    } else if (!m.bump_texname.empty()) {
        const float bm = m.bump_texopt.bump_multiplier;
        if (!std::isfinite(bm)) throw std::runtime_error(name + "map_Bump: -bm must be finite");
        out.normal_map.texture = textures.height_map(m.bump_texname, bm, name + "map_Bump");
    }
    if (!m.alpha_texname.empty()) {  // map_d: a mask of the map's coverage
        out.alpha.mode = AlphaMode::Mask;
        out.alpha.coverage = textures.source(m.alpha_texname, Color(1.0f), Color(1.0f),
                                             TexelMeaning::Coverage, name + "map_d");
    }
    return out;
}

/// Reads the MTL files an OBJ names (mtllib), each checked first as every input file is: a
/// device or a pipe named there would otherwise be read until memory runs out.
class CheckedMtlReader : public tinyobj::MaterialReader {
public:
    CheckedMtlReader(std::filesystem::path dir, const FileScope& files)
        : dir_(std::move(dir)), files_(files) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn,
                    std::string* err) override {
        const std::filesystem::path path = files_.resolve(dir_, name);
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {  // as OBJ readers do: the mesh, no materials
            if (warn) *warn += "material file '" + name + "' not found\n";
            return false;
        }
        std::string problem = input_file_problem(path);
        if (!problem.empty()) throw std::runtime_error("mtllib '" + name + "' " + problem);
        std::ifstream in(path);
        tinyobj::LoadMtl(names, materials, &in, warn, err);
        return true;
    }

private:
    std::filesystem::path dir_;
    const FileScope& files_;
};

}  // namespace

MeshFile read_obj(const std::filesystem::path& path, const FileScope& files) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open");
    CheckedMtlReader mtl(path.parent_path(), files);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, &mtl,
                          /*triangulate=*/true, /*default_vcols_fallback=*/false)) {
        // tinyobjloader's message may run over several lines: the first says what is wrong.
        err = err.substr(0, err.find('\n'));
        throw std::runtime_error(err.empty() ? "cannot parse OBJ" : err);
    }
    MeshFile file;
    MtlTextures textures(path.parent_path(), files, file);
    for (const tinyobj::material_t& m : materials) {
        file.materials.push_back(material_from_mtl(m, textures));
        file.material_names.push_back(m.name);
    }
    bool has_normals = !attrib.normals.empty();
    bool has_uvs = !attrib.texcoords.empty();
    std::map<std::tuple<int, int, int>, uint32_t> vertex_of;
    Mesh& mesh = file.mesh;
    size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3;
    size_t nt = attrib.texcoords.size() / 2;
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& indices = shape.mesh.indices;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            if (shape.mesh.num_face_vertices[f] != 3) throw std::runtime_error("bad face");
            for (int k = 0; k < 3; ++k) {
                const tinyobj::index_t& idx = indices[3 * f + k];
                if (idx.vertex_index < 0 || static_cast<size_t>(idx.vertex_index) >= nv ||
                    (idx.normal_index >= 0 && static_cast<size_t>(idx.normal_index) >= nn) ||
                    (idx.texcoord_index >= 0 && static_cast<size_t>(idx.texcoord_index) >= nt)) {
                    throw std::runtime_error("shape '" + shape.name + "': face " +
                                             std::to_string(f) + " has an index out of range");
                }
                auto key = std::make_tuple(idx.vertex_index, idx.normal_index, idx.texcoord_index);
                auto [it, inserted] =
                    vertex_of.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
                if (inserted) {
                    const float* p = &attrib.vertices[3 * static_cast<size_t>(idx.vertex_index)];
                    mesh.positions.emplace_back(p[0], p[1], p[2]);
                    if (has_normals) {
                        mesh.normals.push_back(
                            idx.normal_index < 0 ? vec3(0.0f)
                                                 : vec3(attrib.normals[3 * idx.normal_index],
                                                        attrib.normals[3 * idx.normal_index + 1],
                                                        attrib.normals[3 * idx.normal_index + 2]));
                    }
                    if (has_uvs) {
                        mesh.uvs.push_back(
                            idx.texcoord_index < 0
                                ? vec2(0.0f)
                                : vec2(attrib.texcoords[2 * idx.texcoord_index],
                                       attrib.texcoords[2 * idx.texcoord_index + 1]));
                    }
                }
                mesh.indices.push_back(it->second);
            }
            int m = shape.mesh.material_ids.empty() ? -1 : shape.mesh.material_ids[f];
            mesh.face_material.push_back(
                m >= 0 && static_cast<size_t>(m) < file.materials.size() ? m : -1);
        }
    }
    if (mesh.indices.empty()) throw std::runtime_error("OBJ file has no faces");
    // Faces without their own normals keep a zero normal; recompute all normals then.
    for (const vec3& n : mesh.normals) {
        if (n == vec3(0.0f)) {
            mesh.normals.clear();
            break;
        }
    }
    bool any_material = false;
    for (int m : mesh.face_material) any_material = any_material || m >= 0;
    if (!any_material) mesh.face_material.clear();
    return file;
}

}  // namespace svetlo
