// materials section and material colours (constants, textures, checkers).
#include <algorithm>
#include <map>

#include "svetlo/core/image_io.h"
#include "svetlo/scene/scene_parts.h"

namespace svetlo {

namespace {

ColorSource optional_color(const JsonNode& node, const char* key, Color fallback, Scene& scene,
                           FileCache& files) {
    auto n = node.find(key);
    return n ? parse_color_source(*n, scene, files) : ColorSource::constant(fallback);
}

float roughness_like(const JsonNode& node, const char* key, float fallback) {
    auto n = node.find(key);
    return n ? n->as_in_range(0.0, 1.0) : fallback;
}

PhongMaterial parse_phong(const JsonNode& node, Scene& scene, FileCache& files, bool blinn) {
    node.expect_object({"type", "ka", "kd", "ks", "shininess", "reflect", "transmit", "ior"});
    PhongMaterial m;
    m.blinn = blinn;
    m.ka = optional_color(node, "ka", Color(0.0f), scene, files);
    m.kd = optional_color(node, "kd", Color(0.8f), scene, files);
    m.ks = optional_color(node, "ks", Color(0.0f), scene, files);
    if (auto n = node.find("shininess")) m.shininess = n->as_non_negative();
    m.reflect = optional_color(node, "reflect", Color(0.0f), scene, files);
    m.transmit = optional_color(node, "transmit", Color(0.0f), scene, files);
    if (auto n = node.find("ior")) m.ior = n->as_positive();
    return m;
}

/// An Abbe number: 0 (no dispersion) or at least 1, which keeps n(lambda) above 1 across the
/// visible range for any ior above 1 (docs/path.md, "Dispersion").
float abbe_number(const JsonNode& n) {
    float v = n.as_non_negative();
    if (v != 0.0f && v < 1.0f) {
        n.fail("must be 0 (no dispersion) or >= 1 (is " + std::to_string(v) + ")");
    }
    return v;
}

/// "dispersion": {"abbe": V} or {"cauchy": [A, B]}, n(lambda) = A + B / lambda^2 with lambda
/// in micrometres. Cauchy's pair becomes the ior at 587.6 nm and the Abbe number it implies.
void parse_dispersion(const JsonNode& node, bool has_ior, DielectricMaterial& m) {
    node.expect_object({"abbe", "cauchy"});
    if (node.has("abbe") == node.has("cauchy")) node.fail("expected one of abbe or cauchy");
    if (auto n = node.find("abbe")) {
        m.abbe = abbe_number(*n);
        return;
    }
    const JsonNode c = node.at("cauchy");
    if (!c.is_array() || c.size() != 2) c.fail("expected [A, B] (B in square micrometres)");
    const vec2 ab(c.at(size_t{0}).as_positive(), c.at(size_t{1}).as_positive());
    if (has_ior) c.fail("gives the ior itself; drop the material's ior");
    constexpr float kD = 0.5876f, kF = 0.4861f, kC = 0.6563f;  // Fraunhofer lines, um
    m.ior = ab.x + ab.y / (kD * kD);
    m.abbe = (m.ior - 1.0f) / (ab.y * (1.0f / (kF * kF) - 1.0f / (kC * kC)));
    if (m.abbe < 1.0f) c.fail("disperses more than an Abbe number of 1 allows");
}

/// "normal_map": {"texture": IMAGE, "scale": s, and a texture's filter and wrap}; the image is
/// data, linear unless told.
NormalMap parse_normal_map(const JsonNode& node, Scene& scene, FileCache& files) {
    if (!node.is_object() || !node.has("texture")) node.fail("expected {\"texture\": IMAGE}");
    node.expect_object({"texture", "scale", "filter", "wrap", "srgb", "max_anisotropy"});
    NormalMap map;
    if (auto n = node.find("scale")) map.scale = n->as_float();
    nlohmann::json texture = node.raw();
    texture.erase("scale");
    map.texture = parse_color_source(JsonNode(texture, node.file(), node.path()), scene, files,
                                     /*srgb=*/false);
    return map;
}

MaterialModel parse_model(const JsonNode& node, Scene& scene, FileCache& files) {
    std::string type =
        node.at("type").as_choice({"lambert", "phong", "blinn_phong", "oren_nayar", "cook_torrance",
                                   "mirror", "dielectric", "emissive"});
    if (type == "lambert") {
        node.expect_object({"type", "albedo"});
        return LambertMaterial{optional_color(node, "albedo", Color(0.8f), scene, files)};
    }
    if (type == "phong" || type == "blinn_phong")
        return parse_phong(node, scene, files, type == "blinn_phong");
    if (type == "oren_nayar") {
        node.expect_object({"type", "albedo", "sigma"});
        OrenNayarMaterial m;
        m.albedo = optional_color(node, "albedo", Color(0.8f), scene, files);
        if (auto n = node.find("sigma")) m.sigma_deg = n->as_in_range(0.0, 90.0);
        return m;
    }
    if (type == "cook_torrance") {
        node.expect_object({"type", "base_color", "roughness", "metallic", "metallic_roughness",
                            "occlusion", "occlusion_strength", "ior", "transmission",
                            "attenuation_color", "attenuation_distance", "clearcoat",
                            "clearcoat_roughness", "clearcoat_normal_map", "specular",
                            "specular_color"});
        CookTorranceMaterial m;
        m.base_color = optional_color(node, "base_color", Color(0.8f), scene, files);
        m.roughness = roughness_like(node, "roughness", 0.5f);
        m.metallic = roughness_like(node, "metallic", 0.0f);
        if (auto n = node.find("metallic_roughness"))  // data, not colour: linear unless told
            m.metallic_roughness = parse_color_source(*n, scene, files, /*srgb=*/false);
        if (auto n = node.find("occlusion"))  // data too: its red channel read
            m.occlusion = parse_color_source(*n, scene, files, /*srgb=*/false);
        m.occlusion_strength = roughness_like(node, "occlusion_strength", 1.0f);
        if (auto n = node.find("ior")) m.ior = static_cast<float>(n->as_in_range(1.0, 10.0));
        if (auto n = node.find("transmission"))  // a share: linear, its red channel read
            m.transmission = parse_color_source(*n, scene, files, /*srgb=*/false);
        if (auto n = node.find("attenuation_color")) {
            m.attenuation_color = n->as_color();
            if (max_component(m.attenuation_color) > 1.0f) n->fail("must lie in [0, 1]");
        }
        if (auto n = node.find("attenuation_distance")) m.attenuation_distance = n->as_positive();
        // The coat's strength (red) and roughness (green): shares, linear unless told.
        if (auto n = node.find("clearcoat"))
            m.clearcoat = parse_color_source(*n, scene, files, false);
        if (auto n = node.find("clearcoat_roughness"))
            m.clearcoat_roughness = parse_color_source(*n, scene, files, false);
        if (auto n = node.find("clearcoat_normal_map"))  // the coat's own, as normal_map
            m.clearcoat_normal = parse_normal_map(*n, scene, files);
        // The specular strength: a share, or a texture read as coverage (its alpha channel,
        // else its one channel: glTF's specularTexture); its F0 tint a colour (sRGB).
        if (auto n = node.find("specular")) {
            m.specular = n->is_object()
                             ? parse_image_source(*n, scene, files, TexelMeaning::Coverage)
                             : ColorSource::constant(Color(n->as_in_range(0.0, 1.0)));
        }
        if (auto n = node.find("specular_color"))
            m.specular_color = parse_color_source(*n, scene, files);
        return m;
    }
    if (type == "mirror") {
        node.expect_object({"type", "reflectance"});
        return MirrorMaterial{optional_color(node, "reflectance", Color(1.0f), scene, files)};
    }
    if (type == "dielectric") {
        node.expect_object({"type", "ior", "abbe", "dispersion"});
        DielectricMaterial m;
        if (auto n = node.find("ior")) m.ior = n->as_positive();
        if (auto n = node.find("abbe")) m.abbe = abbe_number(*n);
        if (auto d = node.find("dispersion")) parse_dispersion(*d, node.has("ior"), m);
        return m;
    }
    node.expect_object({"type", "radiance", "albedo"});
    EmissiveMaterial m;
    m.radiance = optional_color(node, "radiance", Color(1.0f), scene, files);
    m.albedo = optional_color(node, "albedo", Color(0.0f), scene, files);
    return m;
}

/// A material's `alpha` (a number in [0, 1], or a texture read as coverage), `alpha_mode`
/// ("mask" when alpha is given, else "opaque") and `alpha_cutoff`.
Alpha parse_alpha(const JsonNode& material, Scene& scene, FileCache& files) {
    Alpha a;
    if (auto n = material.find("alpha")) {
        a.mode = AlphaMode::Mask;
        a.coverage = n->is_object() ? parse_image_source(*n, scene, files, TexelMeaning::Coverage)
                                    : ColorSource::constant(Color(n->as_in_range(0.0, 1.0)));
    }
    if (auto n = material.find("alpha_mode")) {
        a.mode = n->as_enum(kAlphaModes);
    }
    if (auto n = material.find("alpha_cutoff")) a.cutoff = n->as_in_range(0.0, 1.0);
    return a;
}

}  // namespace

std::filesystem::path named_file(const JsonNode& node, const Scene& scene) {
    try {
        return scene.files.resolve(scene.path.parent_path(), node.as_string());
    } catch (const std::runtime_error& e) {
        node.fail(e.what());
    }
}

size_t texture_bytes_left(const Scene& scene) {
    size_t used = 0;
    for (const TextureImage& t : scene.textures) used += t.bytes();
    return kMaxSceneTextureBytes - std::min(used, kMaxSceneTextureBytes);
}

Material parse_material(const JsonNode& node, Scene& scene, FileCache& files) {
    if (!node.is_object()) node.fail("must be an object");
    // The keys every model takes (docs/scene-format.md, "Keys of every material"), read here
    // once; the rest by the model's own reader.
    nlohmann::json model = node.raw();
    for (const char* key : {"emission", "normal_map", "alpha", "alpha_mode", "alpha_cutoff"})
        model.erase(key);
    Material m = parse_model(JsonNode(model, node.file(), node.path()), scene, files);
    if (auto e = node.find("emission")) m.emission = parse_color_source(*e, scene, files);
    if (auto n = node.find("normal_map")) m.normal_map = parse_normal_map(*n, scene, files);
    m.alpha = parse_alpha(node, scene, files);
    return m;
}

ColorSource parse_color_source(const JsonNode& node, Scene& scene, FileCache& files,
                               bool srgb_default) {
    if (!node.is_object()) return ColorSource::constant(node.as_color());
    ColorSource s;
    if (node.has("checker")) {
        node.expect_object({"checker"});
        JsonNode c = node.at("checker");
        c.expect_object({"a", "b", "scale"});
        s.kind = ColorSource::Kind::Checker;
        s.a = c.at("a").as_color();
        s.b = c.at("b").as_color();
        if (auto n = c.find("scale")) s.scale = n->as_positive();
        return s;
    }
    bool srgb = srgb_default;
    if (auto n = node.find("srgb")) srgb = n->as_bool();
    return parse_image_source(node, scene, files, srgb ? TexelMeaning::Srgb : TexelMeaning::Linear);
}

ColorSource parse_image_source(const JsonNode& node, Scene& scene, FileCache& files,
                               TexelMeaning meaning) {
    if (meaning == TexelMeaning::Coverage)
        node.expect_object({"texture", "filter", "wrap", "max_anisotropy"});
    else
        node.expect_object({"texture", "filter", "wrap", "srgb", "max_anisotropy"});
    ColorSource s;
    s.kind = ColorSource::Kind::Image;
    JsonNode tex = node.at("texture");
    const std::filesystem::path file = named_file(tex, scene);
    if (auto n = node.find("filter")) s.filter = n->as_enum(kTextureFilters);
    if (auto n = node.find("max_anisotropy"))
        s.max_anisotropy = static_cast<int>(n->as_integer(1, 64));
    if (auto n = node.find("wrap")) {  // one mode, or [along u, along v]
        if (n->is_array()) {
            if (n->size() != 2) n->fail("expected one wrap mode, or two: [along u, along v]");
            s.wrap = TextureWraps(n->at(0).as_enum(kTextureWraps), n->at(1).as_enum(kTextureWraps));
        } else {
            s.wrap = n->as_enum(kTextureWraps);
        }
    }
    // One read per file and colour space, however many materials use it.
    std::error_code ec;
    std::string source = std::filesystem::weakly_canonical(file, ec).string() +
                         (meaning == TexelMeaning::Srgb     ? " (sRGB)"
                          : meaning == TexelMeaning::Linear ? " (linear)"
                                                            : " (coverage)");
    auto known = std::find(scene.texture_sources.begin(), scene.texture_sources.end(), source);
    if (known != scene.texture_sources.end()) {
        s.texture = static_cast<int>(known - scene.texture_sources.begin());
        return s;
    }
    // Memory: each texture within kMaxTextureBytes, all of them within kMaxSceneTextureBytes,
    // checked from each file's header before it is decoded.
    const size_t left = texture_bytes_left(scene);
    try {
        scene.textures.push_back(
            files.read_texture(file, meaning, std::min(kMaxTextureBytes, left), tex.path()));
    } catch (const Error& e) {
        tex.fail("cannot read texture '" + tex.as_string() + "': " + e.message());
    }
    scene.texture_sources.push_back(source);
    s.texture = static_cast<int>(scene.textures.size()) - 1;
    return s;
}

void parse_environment(const JsonNode& node, Scene& scene, FileCache& files) {
    node.expect_object({"file", "scale", "rotate"});
    const JsonNode file = node.at("file");
    const std::filesystem::path path = named_file(file, scene);
    const std::string ext = lower_extension(path);
    if (ext != ".hdr" && ext != ".exr" && ext != ".pfm")
        file.fail("an environment is a linear image: .hdr, .exr or .pfm (is '" + ext + "')");
    EnvironmentSettings e;
    if (auto n = node.find("scale")) e.scale = n->as_color();
    if (auto n = node.find("rotate")) e.rotate_deg = n->as_float();
    const size_t left = texture_bytes_left(scene);
    try {
        // A texel that is not finite is refused by read_texture, naming it; one below zero
        // (lossy EXR compression's) is made 0.
        scene.textures.push_back(files.read_texture(path, TexelMeaning::Linear,
                                                    std::min(kMaxTextureBytes, left), file.path(),
                                                    NegativeTexels::ClampToZero));
    } catch (const Error& err) {
        file.fail("cannot read environment '" + file.as_string() + "': " + err.message());
    }
    scene.texture_sources.push_back(path.string() + " (environment)");
    e.texture = static_cast<int>(scene.textures.size()) - 1;
    scene.environment = e;
}

void parse_materials(const JsonNode& node, Scene& scene, FileCache& files) {
    if (!node.is_object()) node.fail("must be an object mapping names to materials");
    for (const auto& [name, value] : node.raw().items()) {
        if (!name.empty() && name[0] == '_') continue;
        JsonNode m(value, node.file(), node.path() + "." + name);
        scene.materials.push_back(parse_material(m, scene, files));
        scene.material_names.push_back(name);
    }
}

}  // namespace svetlo
