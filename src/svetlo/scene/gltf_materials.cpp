#include "svetlo/scene/gltf_materials.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "svetlo/core/image_io.h"
#include "svetlo/core/input_file.h"
#include "svetlo/core/parallel.h"

namespace svetlo {

namespace {

/// glTF's textures as svetlo's: each image decoded once per colour space (sRGB for base
/// colour and emission, linear for data), each texture reference a ColorSource with the
/// texture's sampler and KHR_texture_transform.
class GltfTextures {
public:
    GltfTextures(const tinygltf::Model& model, const GltfImageFiles& image_files, MeshFile& file)
        : model_(model), image_files_(image_files), file_(file) {}

    /// The ColorSource of a material's texture reference, times `factor`; throws for a
    /// texture or image that is missing or does not decode.
    ColorSource source(int texture, int tex_coord, const tinygltf::ExtensionMap& extensions,
                       Color factor, TexelMeaning meaning, const std::string& what) {
        if (texture < 0 || static_cast<size_t>(texture) >= model_.textures.size())
            throw std::runtime_error(what + ": texture " + std::to_string(texture) + " missing");
        const tinygltf::Texture& t = model_.textures[static_cast<size_t>(texture)];
        ColorSource s;
        s.kind = ColorSource::Kind::Image;
        s.uv_set = texture_set(tex_coord, what);
        // EXT_texture_webp names the WebP image in place of `source` (a fallback, or none).
        int source = t.source;
        if (auto webp = t.extensions.find("EXT_texture_webp");
            webp != t.extensions.end() && reads_webp() && webp->second.Has("source"))
            source = webp->second.Get("source").GetNumberAsInt();
        s.texture = image(source, meaning, what);
        s.factor = factor;
        if (t.sampler >= 0 && static_cast<size_t>(t.sampler) < model_.samplers.size()) {
            const tinygltf::Sampler& sampler = model_.samplers[static_cast<size_t>(t.sampler)];
            if (sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST)
                s.filter = TextureFilter::Nearest;
            // wrapS along u, wrapT along v (BoxTextured's u runs to 6 under mirrored repeat,
            // with v clamped in [0, 1]); an unknown code repeats, glTF's default.
            const auto wrap = [](int code) {
                return code == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? TextureWrap::Clamp
                       : code == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureWrap::Mirror
                                                                       : TextureWrap::Repeat;
            };
            s.wrap = TextureWraps(wrap(sampler.wrapS), wrap(sampler.wrapT));
        }
        if (auto ext = extensions.find("KHR_texture_transform"); ext != extensions.end())
            transform(ext->second, s);
        return s;
    }

    /// The same for a texture reference inside an extension (a JSON object with `index`,
    /// `texCoord` and KHR_texture_transform), linear data unless `meaning` says otherwise.
    ColorSource source(const tinygltf::Value& ref, Color factor, const std::string& what,
                       TexelMeaning meaning = TexelMeaning::Linear) {
        const int index = ref.Has("index") ? ref.Get("index").GetNumberAsInt() : -1;
        const int set = ref.Has("texCoord") ? ref.Get("texCoord").GetNumberAsInt() : 0;
        tinygltf::ExtensionMap extensions;
        if (ref.Has("extensions") && ref.Get("extensions").Has("KHR_texture_transform"))
            extensions["KHR_texture_transform"] =
                ref.Get("extensions").Get("KHR_texture_transform");
        return source(index, set, extensions, factor, meaning, what);
    }

private:
    /// A texCoord as a Varyings set: svetlo reads TEXCOORD_0 and TEXCOORD_1.
    static int texture_set(int tex_coord, const std::string& what) {
        if (tex_coord < 0 || tex_coord > 1)
            throw std::runtime_error(what + ": TEXCOORD_" + std::to_string(tex_coord) +
                                     " is not read (svetlo reads TEXCOORD_0 and TEXCOORD_1)");
        return tex_coord;
    }

    /// KHR_texture_transform: uv' = T R S uv in glTF's texture space (its v runs down), mapped
    /// into svetlo's (v up) by F = (u, 1 - v) on both sides: M = F T R S F. R maps (u, v) to
    /// (u cos r + v sin r, -u sin r + v cos r): the sample model TextureTransformTest's arrow
    /// then points at its green marker (the opposite sign points at the red one).
    static void transform(const tinygltf::Value& ext, ColorSource& s) {
        auto number = [&](const char* key, int index, double fallback) {
            if (!ext.Has(key)) return fallback;
            const tinygltf::Value& v = ext.Get(key);
            if (index < 0) return v.GetNumberAsDouble();
            return v.IsArray() && v.ArrayLen() > static_cast<size_t>(index)
                       ? v.Get(index).GetNumberAsDouble()
                       : fallback;
        };
        // Its texCoord, when given, replaces the texture reference's.
        if (ext.Has("texCoord"))
            s.uv_set = texture_set(ext.Get("texCoord").GetNumberAsInt(), "KHR_texture_transform");
        const float ox = static_cast<float>(number("offset", 0, 0.0));
        const float oy = static_cast<float>(number("offset", 1, 0.0));
        const float r = static_cast<float>(number("rotation", -1, 0.0));
        const float sx = static_cast<float>(number("scale", 0, 1.0));
        const float sy = static_cast<float>(number("scale", 1, 1.0));
        for (float v : {ox, oy, r, sx, sy})
            if (!std::isfinite(v)) throw std::runtime_error("KHR_texture_transform: not finite");
        const mat3 t(1, 0, 0, 0, 1, 0, ox, oy, 1);  // column-major, as the extension writes it
        const mat3 rot(std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r), 0, 0, 0, 1);
        const mat3 scale(sx, 0, 0, 0, sy, 0, 0, 0, 1);
        const mat3 flip(1, 0, 0, 0, -1, 0, 0, 1, 1);
        s.uv_transform = flip * t * rot * scale * flip;
        s.transformed = true;
    }

    /// The index in file_.textures of image `index` decoded as `meaning` says (by decode_all:
    /// until then its place is held).
    int image(int index, TexelMeaning meaning, const std::string& what) {
        if (index < 0 || static_cast<size_t>(index) >= model_.images.size())
            throw std::runtime_error(what + ": image " + std::to_string(index) + " missing");
        const auto key = std::make_pair(index, meaning);
        if (auto known = made_.find(key); known != made_.end()) return known->second;
        const tinygltf::Image& im = model_.images[static_cast<size_t>(index)];
        const std::string name =
            "image " + std::to_string(index) +
            (im.uri.empty() || im.uri.rfind("data:", 0) == 0 ? "" : " '" + im.uri + "'");
        // The encoded bytes (keep_encoded), decoded here to 8-bit RGB: a 16-bit PNG keeps its
        // high bytes, grey is repeated; or to coverage, its alpha channel. The size is checked
        // from the header before anything is decoded.
        if (names_network(im.uri)) throw std::runtime_error(what + ": " + name + " " + kNetwork);
        file_.textures.emplace_back();
        const int made = static_cast<int>(file_.textures.size()) - 1;
        const auto file = image_files_.find(index);
        pending_.push_back({&im, file == image_files_.end() ? std::string() : file->second, meaning,
                            static_cast<size_t>(made), what + ": " + name});
        made_[key] = made;
        return made;
    }

public:
    /// Decodes the images image() named, on all cores (a model's textures are most of its
    /// loading time); a failure is the first image's in the file's order, whatever the
    /// threads.
    void decode_all() {
        std::vector<std::string> errors(pending_.size());
        parallel_indices(pending_.size(), 0, [&](size_t k) {
            const Pending& p = pending_[k];
            try {
                std::vector<unsigned char> read;
                if (!p.file.empty()) read = read_input_file(p.file);
                const std::vector<unsigned char>& bytes = p.file.empty() ? p.image->image : read;
                file_.textures[p.slot] =
                    decode_texture(bytes.data(), bytes.size(), p.meaning, kMaxTextureBytes);
            } catch (const std::exception& e) {
                errors[k] = p.label + " does not decode: " + e.what();
            }
        });
        for (const std::string& e : errors)
            if (!e.empty()) throw std::runtime_error(e);
    }

private:
    const tinygltf::Model& model_;
    const GltfImageFiles& image_files_;
    MeshFile& file_;
    std::map<std::pair<int, TexelMeaning>, int> made_;
    struct Pending {
        const tinygltf::Image* image;
        std::string file;  // read before decoding; empty: the image holds its bytes
        TexelMeaning meaning;
        size_t slot;        // in file_.textures
        std::string label;  // "material 2 baseColorTexture: image 0 'a.png'"
    };
    std::vector<Pending> pending_;
};

/// The metallic-roughness surface: base colour, metallic and roughness, occlusion. Every
/// factor checked (file_color): [-1, 2, 1e39] is refused.
CookTorranceMaterial metallic_roughness(const tinygltf::Material& m, GltfTextures& textures,
                                        const std::string& name) {
    const auto& pbr = m.pbrMetallicRoughness;
    Color base(1.0f);
    if (pbr.baseColorFactor.size() >= 3) {
        base = file_color(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                          name + " baseColorFactor");
    }
    CookTorranceMaterial ct;
    ct.base_color = ColorSource::constant(base);
    if (pbr.baseColorTexture.index >= 0)
        ct.base_color = textures.source(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                        pbr.baseColorTexture.extensions, base, TexelMeaning::Srgb,
                                        name + " baseColorTexture");
    ct.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
    ct.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
    if (pbr.metallicRoughnessTexture.index >= 0)
        ct.metallic_roughness = textures.source(
            pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
            pbr.metallicRoughnessTexture.extensions, Color(1.0f), TexelMeaning::Linear,
            name + " metallicRoughnessTexture");
    if (m.occlusionTexture.index >= 0) {
        ct.occlusion = textures.source(m.occlusionTexture.index, m.occlusionTexture.texCoord,
                                       m.occlusionTexture.extensions, Color(1.0f),
                                       TexelMeaning::Linear, name + " occlusionTexture");
        ct.occlusion_strength =
            static_cast<float>(std::clamp(m.occlusionTexture.strength, 0.0, 1.0));
    }
    return ct;
}

/// An extension's factor `key` in [0, 1] (0 when absent), as a grey colour.
Color unit_factor(const tinygltf::Value& ext, const char* key, const std::string& name) {
    const double f = ext.Has(key) ? ext.Get(key).GetNumberAsDouble() : 0.0;
    if (!(f >= 0.0 && f <= 1.0)) throw std::runtime_error(name + " " + key + " must lie in [0, 1]");
    return Color(static_cast<float>(f));
}

/// A factor times the texture `texture_key` of an extension where it has one (its channel
/// read as linear data), else the factor alone.
ColorSource factor_texture(const tinygltf::Value& ext, Color factor, const char* texture_key,
                           GltfTextures& textures, const std::string& name) {
    if (!ext.Has(texture_key) || is_black(factor)) return ColorSource::constant(factor);
    return textures.source(ext.Get(texture_key), factor, name + " " + texture_key);
}

/// KHR_materials_specular: `specularFactor` (1) times `specularTexture`'s alpha channel, the
/// dielectric's specular strength; `specularColorFactor` (white, each channel >= 0) times
/// `specularColorTexture` (sRGB), its F0's tint.
void read_specular(const tinygltf::Value& ext, GltfTextures& textures, const std::string& name,
                   CookTorranceMaterial& ct) {
    const Color strength =
        ext.Has("specularFactor") ? unit_factor(ext, "specularFactor", name) : Color(1.0f);
    ct.specular = ColorSource::constant(strength);
    if (ext.Has("specularTexture") && !is_black(strength))
        ct.specular = textures.source(ext.Get("specularTexture"), strength,
                                      name + " specularTexture", TexelMeaning::Coverage);
    Color tint(1.0f);
    if (ext.Has("specularColorFactor")) {
        const tinygltf::Value& c = ext.Get("specularColorFactor");
        if (!c.IsArray() || c.ArrayLen() != 3)
            throw std::runtime_error(name + " specularColorFactor must be 3 numbers");
        tint = file_color(c.Get(0).GetNumberAsDouble(), c.Get(1).GetNumberAsDouble(),
                          c.Get(2).GetNumberAsDouble(), name + " specularColorFactor");
    }
    ct.specular_color = ColorSource::constant(tint);
    if (ext.Has("specularColorTexture") && !is_black(tint))
        ct.specular_color = textures.source(ext.Get("specularColorTexture"), tint,
                                            name + " specularColorTexture", TexelMeaning::Srgb);
}

/// KHR_materials_ior, _transmission (its texture's red channel), _clearcoat (strength red,
/// roughness green, and its own normal map: without one the coat is not normal-mapped) and
/// _volume (the inside's absorption; its thickness, for rasterizers that fake the inside, is
/// not needed: the ray tracers trace it).
void read_extensions(const tinygltf::Material& m, GltfTextures& textures, const std::string& name,
                     CookTorranceMaterial& ct) {
    if (auto ior = m.extensions.find("KHR_materials_ior");
        ior != m.extensions.end() && ior->second.Has("ior")) {
        const double value = ior->second.Get("ior").GetNumberAsDouble();
        if (!std::isfinite(value))
            throw std::runtime_error(name + " KHR_materials_ior: not finite");
        ct.ior = static_cast<float>(std::clamp(value, 1.0, 10.0));
    }
    if (auto tr = m.extensions.find("KHR_materials_transmission"); tr != m.extensions.end())
        ct.transmission =
            factor_texture(tr->second, unit_factor(tr->second, "transmissionFactor", name),
                           "transmissionTexture", textures, name);
    if (auto cc = m.extensions.find("KHR_materials_clearcoat"); cc != m.extensions.end()) {
        const tinygltf::Value& v = cc->second;
        ct.clearcoat = factor_texture(v, unit_factor(v, "clearcoatFactor", name),
                                      "clearcoatTexture", textures, name);
        ct.clearcoat_roughness = factor_texture(v, unit_factor(v, "clearcoatRoughnessFactor", name),
                                                "clearcoatRoughnessTexture", textures, name);
        if (v.Has("clearcoatNormalTexture")) {  // linear, its scale as normalTexture's
            const tinygltf::Value& t = v.Get("clearcoatNormalTexture");
            ct.clearcoat_normal.texture =
                textures.source(t, Color(1.0f), name + " clearcoatNormalTexture");
            if (t.Has("scale")) {
                const double scale = t.Get("scale").GetNumberAsDouble();
                if (!std::isfinite(scale))
                    throw std::runtime_error(name + " clearcoatNormalTexture scale: not finite");
                ct.clearcoat_normal.scale = static_cast<float>(scale);
            }
        }
    }
    if (auto vol = m.extensions.find("KHR_materials_volume"); vol != m.extensions.end()) {
        const tinygltf::Value& v = vol->second;
        if (v.Has("attenuationDistance")) {
            const double d = v.Get("attenuationDistance").GetNumberAsDouble();
            if (!(d > 0.0)) throw std::runtime_error(name + " attenuationDistance must be > 0");
            ct.attenuation_distance = static_cast<float>(std::min(d, 1e30));
        }
        if (v.Has("attenuationColor") && v.Get("attenuationColor").ArrayLen() == 3) {
            const tinygltf::Value& c = v.Get("attenuationColor");
            ct.attenuation_color =
                file_color(c.Get(0).GetNumberAsDouble(), c.Get(1).GetNumberAsDouble(),
                           c.Get(2).GetNumberAsDouble(), name + " attenuationColor");
            if (max_component(ct.attenuation_color) > 1.0f)
                throw std::runtime_error(name + " attenuationColor must lie in [0, 1]");
        }
    }
    if (auto sp = m.extensions.find("KHR_materials_specular"); sp != m.extensions.end())
        read_specular(sp->second, textures, name, ct);
}

/// Emission on the metallic-roughness surface (the material's `emission`): emissiveFactor
/// times KHR_materials_emissive_strength, times the texture (sRGB) when there is one.
ColorSource emission_of(const tinygltf::Material& m, GltfTextures& textures,
                        const std::string& name) {
    double strength = 1.0;
    auto ext = m.extensions.find("KHR_materials_emissive_strength");
    if (ext != m.extensions.end() && ext->second.Has("emissiveStrength"))
        strength = ext->second.Get("emissiveStrength").GetNumberAsDouble();
    Color emission(0.0f);
    if (m.emissiveFactor.size() == 3) {
        emission = file_color(strength * m.emissiveFactor[0], strength * m.emissiveFactor[1],
                              strength * m.emissiveFactor[2],
                              name + " emissiveFactor times emissiveStrength");
    }
    if (!(max_component(emission) > 0.0f)) return ColorSource{};
    if (m.emissiveTexture.index < 0) return ColorSource::constant(emission);
    return textures.source(m.emissiveTexture.index, m.emissiveTexture.texCoord,
                           m.emissiveTexture.extensions, emission, TexelMeaning::Srgb,
                           name + " emissiveTexture");
}

/// alphaMode: MASK with alphaCutoff, BLEND; coverage the base colour's alpha (its
/// texture's alpha channel, linear) times the factor's.
Alpha alpha_of(const tinygltf::Material& m, GltfTextures& textures, const std::string& name) {
    Alpha alpha;
    if (m.alphaMode != "MASK" && m.alphaMode != "BLEND") return alpha;
    const auto& pbr = m.pbrMetallicRoughness;
    alpha.mode = m.alphaMode == "MASK" ? AlphaMode::Mask : AlphaMode::Blend;
    const double a = pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[3] : 1.0;
    if (!(a >= 0.0 && a <= 1.0))
        throw std::runtime_error(name + " baseColorFactor: alpha must lie in [0, 1]");
    alpha.coverage = ColorSource::constant(Color(static_cast<float>(a)));
    if (pbr.baseColorTexture.index >= 0)
        alpha.coverage =
            textures.source(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                            pbr.baseColorTexture.extensions, Color(static_cast<float>(a)),
                            TexelMeaning::Coverage, name + " baseColorTexture");
    if (!(m.alphaCutoff >= 0.0 && m.alphaCutoff <= 1.0))
        throw std::runtime_error(name + " alphaCutoff must lie in [0, 1]");
    alpha.cutoff = static_cast<float>(m.alphaCutoff);
    return alpha;
}

Material material_from_gltf(const tinygltf::Material& m, GltfTextures& textures) {
    const std::string name = "material '" + m.name + "'";
    CookTorranceMaterial ct = metallic_roughness(m, textures, name);
    if (m.extensions.count("KHR_materials_unlit")) {
        // KHR_materials_unlit: the surface shows its base colour whatever the light, which in
        // radiometric terms is a black surface that emits it (docs/scene-format.md, "Mesh
        // files"): the base colour (sRGB, times its factor and COLOR_0) as emitted radiance,
        // with its alpha; the other textures are not read.
        Material out = LambertMaterial{ColorSource::constant(Color(0.0f))};
        out.emission = ct.base_color;
        out.alpha = alpha_of(m, textures, name);
        return out;
    }
    read_extensions(m, textures, name, ct);
    Material out = ct;
    out.emission = emission_of(m, textures, name);
    if (m.normalTexture.index >= 0) {
        out.normal_map.texture = textures.source(m.normalTexture.index, m.normalTexture.texCoord,
                                                 m.normalTexture.extensions, Color(1.0f),
                                                 TexelMeaning::Linear, name + " normalTexture");
        out.normal_map.scale = static_cast<float>(m.normalTexture.scale);
    }
    out.alpha = alpha_of(m, textures, name);
    return out;
}

}  // namespace

void read_gltf_materials(const tinygltf::Model& model, const GltfImageFiles& image_files,
                         MeshFile& file) {
    GltfTextures textures(model, image_files, file);
    for (const tinygltf::Material& m : model.materials) {
        file.materials.push_back(material_from_gltf(m, textures));
        file.material_names.push_back(m.name);
    }
    textures.decode_all();
}

}  // namespace svetlo
