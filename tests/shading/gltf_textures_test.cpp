// glTF materials with their textures (docs/scene-format.md, "Mesh files"): base colour and
// emission in sRGB times their factors, metallicRoughness linear (G roughness, B metallic), a
// sampler's filter and wrap, KHR_texture_transform; and what a bad texture gets.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "svetlo/core/image_io.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/shading/bsdf.h"
#include "svetlo/shading/normal_map.h"
#include "svetlo/shading/texture.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A folder with a 2 x 1 PNG (left texel sRGB code 255/0/0, right 0/128/255 as linear
/// values after decoding) and a glTF of one triangle whose material `material` is given.
class GltfTextures : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() /
              ("svetlo_gltf_textures_" +
               std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::create_directories(dir);
        Image im(2, 1);
        im.at(0, 0) = Color(1.0f, 0.0f, 0.0f);
        im.at(1, 0) = Color(0.0f, 0.5f, 1.0f);
        // Data: the PNG holds the codes of these values (linear meaning: code = value * 255).
        write_image(dir / "tex.png", im, PixelMeaning::Data, 1.0f, "test");
    }
    void TearDown() override { fs::remove_all(dir); }

    MeshFile read(const json& material, const json& extra = json::object()) {
        std::ifstream in(fs::path(SVETLO_TEST_DATA) / "triangle.gltf");
        json g = json::parse(in);
        g["materials"] = {material};
        g["meshes"][0]["primitives"][0]["material"] = 0;
        g["images"] = {{{"uri", "tex.png"}}};
        g["textures"] = {{{"source", 0}, {"sampler", 0}}};
        g["samplers"] = {
            {{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};  // nearest, clamp
        g.merge_patch(extra);
        std::ofstream(dir / "m.gltf") << g.dump();
        return read_mesh_file(dir / "m.gltf");
    }

    fs::path dir;
};

/// The colour of `s` at uv, with the file's textures.
Color at(const ColorSource& s, vec2 uv, const MeshFile& f) { return eval_color(s, uv, f.textures); }

TEST_F(GltfTextures, BaseColourIsSrgbTimesItsFactor) {
    const MeshFile f =
        read({{"pbrMetallicRoughness",
               {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {0.5, 1, 1, 1}}}}});
    const auto& ct = std::get<CookTorranceMaterial>(f.materials[0].model);
    ASSERT_EQ(ct.base_color.kind, ColorSource::Kind::Image);
    EXPECT_EQ(ct.base_color.filter, TextureFilter::Nearest);
    EXPECT_EQ(ct.base_color.wrap, TextureWrap::Clamp);
    const Color left = at(ct.base_color, vec2(0.25f, 0.5f), f);
    EXPECT_NEAR(left.r, 0.5f, 1e-6f);  // code 255 is 1 in sRGB, times 0.5
    const Color right = at(ct.base_color, vec2(0.75f, 0.5f), f);
    EXPECT_NEAR(right.g, 0.2158605f,
                1e-4f);  // code 128 decoded as sRGB: ((128/255 + 0.055) / 1.055)^2.4
    EXPECT_NEAR(right.b, 1.0f, 1e-6f);
}

TEST_F(GltfTextures, EachAxisWrapsAsItsSamplerSays) {
    // wrapS mirrored repeat, wrapT clamp (BoxTextured's sampler); then repeat and mirrored.
    const json base = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    const MeshFile f = read(base, {{"samplers", {{{"wrapS", 33648}, {"wrapT", 33071}}}}});
    const auto& s = std::get<CookTorranceMaterial>(f.materials[0].model).base_color;
    EXPECT_EQ(s.wrap, TextureWraps(TextureWrap::Mirror, TextureWrap::Clamp));
    // The left texel (red) at u = 0.25, read backward at 1.75; clamped in v.
    EXPECT_NEAR(at(s, vec2(1.75f, 3.5f), f).r, 1.0f, 1e-6f);
    EXPECT_NEAR(at(s, vec2(1.25f, 3.5f), f).b, 1.0f, 1e-6f);
    const MeshFile g = read(base, {{"samplers", {{{"wrapS", 10497}, {"wrapT", 33648}}}}});
    EXPECT_EQ(std::get<CookTorranceMaterial>(g.materials[0].model).base_color.wrap,
              TextureWraps(TextureWrap::Repeat, TextureWrap::Mirror));
}

TEST_F(GltfTextures, MetallicRoughnessIsLinearDataScalingTheFactors) {
    const MeshFile f = read({{"pbrMetallicRoughness",
                              {{"metallicRoughnessTexture", {{"index", 0}}},
                               {"roughnessFactor", 0.8},
                               {"metallicFactor", 1.0}}}});
    // The right texel: G = 128/255 (linear), B = 1: roughness 0.8 * 0.502, metallic 1.
    const Bsdf b = make_bsdf(f.materials[0], vec2(0.75f, 0.5f), f.textures);
    EXPECT_NEAR(b.alpha, square(0.8f * 128.0f / 255.0f), 1e-5f);
    EXPECT_EQ(b.diffuse, Color(0.0f));  // metallic: no diffuse part
    const Bsdf left = make_bsdf(f.materials[0], vec2(0.25f, 0.5f), f.textures);
    EXPECT_NEAR(left.alpha, 1e-3f, 1e-7f);     // G = 0: the smoothest GGX svetlo draws
    EXPECT_NEAR(left.diffuse.r, 1.0f, 1e-6f);  // B = 0: a dielectric of glTF's base colour, 1
}

TEST_F(GltfTextures, EmissionIsTheTextureTimesFactorAndStrengthOnAnyMaterial) {
    const MeshFile f =
        read({{"emissiveTexture", {{"index", 0}}},
              {"emissiveFactor", {1, 1, 0.5}},
              {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}});
    ASSERT_TRUE(std::holds_alternative<CookTorranceMaterial>(f.materials[0].model));
    const Bsdf b = make_bsdf(f.materials[0], vec2(0.25f, 0.5f), f.textures);
    EXPECT_NEAR(b.emission.r, 4.0f, 1e-5f);
    EXPECT_EQ(b.emission.g, 0.0f);
    const Bsdf dark = make_bsdf(f.materials[0], vec2(0.75f, 0.5f), f.textures);
    EXPECT_NEAR(dark.emission.b, 2.0f, 1e-5f);  // 1 * 4 * 0.5
    // No emissive factor: no emission, whatever the texture (glTF's default factor is 0).
    const MeshFile off = read({{"emissiveTexture", {{"index", 0}}}});
    EXPECT_TRUE(off.materials[0].emission.is_black());
}

TEST_F(GltfTextures, UnlitIsABlackSurfaceEmittingItsBaseColourWithItsAlpha) {
    const MeshFile f =
        read({{"pbrMetallicRoughness",
               {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {0.5, 1, 1, 0.4}}}},
              {"alphaMode", "BLEND"},
              {"extensions", {{"KHR_materials_unlit", json::object()}}}},
             {{"extensionsUsed", {"KHR_materials_unlit"}}});
    EXPECT_TRUE(f.warnings.empty());
    const Material& m = f.materials[0];
    const Bsdf left = make_bsdf(m, vec2(0.25f, 0.5f), f.textures);
    EXPECT_EQ(left.diffuse, Color(0.0f));
    EXPECT_EQ(left.specular, Color(0.0f));
    EXPECT_NEAR(left.emission.r, 0.5f, 1e-6f);  // code 255 in sRGB, times 0.5
    const Bsdf right = make_bsdf(m, vec2(0.75f, 0.5f), f.textures);
    EXPECT_NEAR(right.emission.g, 0.2158605f, 1e-4f);  // code 128 decoded as sRGB
    EXPECT_EQ(m.alpha.mode, AlphaMode::Blend);
    EXPECT_NEAR(at(m.alpha.coverage, vec2(0.25f, 0.5f), f).r, 0.4f, 1e-6f);
}

TEST_F(GltfTextures, NormalTextureIsLinearWithItsScale) {
    const MeshFile f = read({{"normalTexture", {{"index", 0}, {"scale", 0.5}}}});
    const NormalMap& map = f.materials[0].normal_map;
    ASSERT_TRUE(map.present());
    EXPECT_EQ(map.scale, 0.5f);
    EXPECT_NEAR(at(map.texture, vec2(0.75f, 0.5f), f).g, 128.0f / 255.0f, 1e-6f);  // linear
    EXPECT_FALSE(read(json::object()).materials[0].normal_map.present());
}

TEST_F(GltfTextures, AlphaModeMaskAndBlendReadTheBaseColoursAlphaTimesItsFactor) {
    // An RGBA image in place of the RGB one: alpha 0 on the left, 200 on the right.
    const unsigned char texels[8] = {255, 0, 0, 0, 0, 0, 255, 200};
    ASSERT_NE(stbi_write_png((dir / "tex.png").c_str(), 2, 1, 4, texels, 8), 0);
    const MeshFile mask =
        read({{"alphaMode", "MASK"},
              {"alphaCutoff", 0.3},
              {"pbrMetallicRoughness",
               {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {1, 1, 1, 0.5}}}}});
    const Alpha& a = mask.materials[0].alpha;
    EXPECT_EQ(a.mode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(a.cutoff, 0.3f);
    EXPECT_EQ(at(a.coverage, vec2(0.25f, 0.5f), mask).r, 0.0f);
    EXPECT_NEAR(at(a.coverage, vec2(0.75f, 0.5f), mask).r, 0.5f * 200.0f / 255.0f, 1e-6f);
    // The colour is still the image's (sRGB), not its alpha.
    const auto& ct = std::get<CookTorranceMaterial>(mask.materials[0].model);
    EXPECT_NEAR(at(ct.base_color, vec2(0.75f, 0.5f), mask).b, 1.0f, 1e-6f);
    const MeshFile blend = read(
        {{"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.25}}}}});
    EXPECT_EQ(blend.materials[0].alpha.mode, AlphaMode::Blend);
    EXPECT_EQ(blend.materials[0].alpha.coverage.value, Color(0.25f));
    EXPECT_EQ(read(json::object()).materials[0].alpha.mode, AlphaMode::Opaque);
}

TEST_F(GltfTextures, ARequiredExtensionNotReadRefusesTheFileAnOptionalOneWarns) {
    try {
        read(json::object(), {{"extensionsUsed", {"KHR_materials_sheen"}},
                              {"extensionsRequired", {"KHR_materials_sheen"}}});
        ADD_FAILURE() << "a required extension svetlo does not read was ignored";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("extensionsRequired names 'KHR_materials_sheen'"),
                  std::string::npos)
            << e.what();
    }
    const MeshFile f =
        read(json::object(), {{"extensionsUsed", {"EXT_lights_ies", "KHR_texture_transform"}}});
    ASSERT_EQ(f.warnings.size(), 1u);
    EXPECT_EQ(f.warnings[0], "extension 'EXT_lights_ies' is not read: ignored");
    EXPECT_NO_THROW(read(json::object(), {{"extensionsUsed", {"KHR_texture_transform"}},
                                          {"extensionsRequired", {"KHR_texture_transform"}}}));
}

TEST_F(GltfTextures, ATextureOfASetPastTheSecondIsRefusedNamingTheMaterial) {
    const json material = {
        {"name", "paint"},
        {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 2}}}}}};
    try {
        read(material);
        ADD_FAILURE() << "TEXCOORD_2 was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("material 'paint' baseColorTexture: TEXCOORD_2"),
                  std::string::npos)
            << e.what();
    }
    const json occlusion = {
        {"occlusionTexture", {{"index", 0}, {"texCoord", 1}, {"strength", 0.25}}}};
    const auto& ct = std::get<CookTorranceMaterial>(read(occlusion).materials[0].model);
    EXPECT_EQ(ct.occlusion.uv_set, 1);
    EXPECT_EQ(ct.occlusion_strength, 0.25f);
}

TEST_F(GltfTextures, EXTTextureWebpReadsTheWebpImageInPlaceOfTheFallback) {
    if (!reads_webp()) GTEST_SKIP() << "this build has no libwebp";
    // A lossless 2 x 1 WebP (libwebp's WebPEncodeLosslessRGBA): left (255, 0, 0) of alpha 0,
    // right (0, 128, 255) of alpha 200.
    const unsigned char webp[38] = {82, 73,  70, 70,  30,  0,  0,  0,  87, 69,  66,  80, 86,
                                    80, 56,  76, 18,  0,   0,  0,  47, 1,  0,   0,   16, 15,
                                    48, 128, 49, 255, 131, 28, 56, 42, 16, 209, 255, 0};
    std::ofstream(dir / "tex.webp", std::ios::binary)
        .write(reinterpret_cast<const char*>(webp), sizeof webp);
    write_image(dir / "fallback.png", Image(1, 1, Color(0.5f)), PixelMeaning::Data, 1.0f, "test");
    const json extra = {
        {"extensionsUsed", {"EXT_texture_webp"}},
        {"images", {{{"uri", "fallback.png"}}, {{"uri", "tex.webp"}}}},
        {"textures", {{{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}}}}};
    const MeshFile f = read(
        {{"alphaMode", "MASK"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
        extra);
    EXPECT_TRUE(f.warnings.empty());
    const auto& ct = std::get<CookTorranceMaterial>(f.materials[0].model);
    const Color right = at(ct.base_color, vec2(0.75f, 0.5f), f);
    EXPECT_NEAR(right.g, 0.2158605f, 1e-4f);  // code 128 in sRGB, not the fallback's grey
    EXPECT_NEAR(right.b, 1.0f, 1e-6f);
    EXPECT_EQ(at(f.materials[0].alpha.coverage, vec2(0.25f, 0.5f), f).r, 0.0f);
    EXPECT_NEAR(at(f.materials[0].alpha.coverage, vec2(0.75f, 0.5f), f).r, 200.0f / 255.0f, 1e-6f);
    // A .webp named by a scene's texture key reads the same way.
    const TextureImage t =
        read_texture(dir / "tex.webp", TexelMeaning::Linear, kMaxTextureBytes, "t");
    EXPECT_NEAR(t.texel(1, 0).g, 128.0f / 255.0f, 1e-6f);
    // A truncated one names the image.
    std::ofstream(dir / "tex.webp", std::ios::binary)
        .write(reinterpret_cast<const char*>(webp), 20);
    try {
        read({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}, extra);
        ADD_FAILURE() << "a truncated WebP was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("image 1 'tex.webp' does not decode"),
                  std::string::npos)
            << e.what();
    }
}

TEST_F(GltfTextures, IorTransmissionVolumeAndClearcoatAreRead) {
    const json ext = {
        {"KHR_materials_ior", {{"ior", 2.0}}},
        {"KHR_materials_transmission", {{"transmissionFactor", 0.5}}},
        {"KHR_materials_volume", {{"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 1, 1}}}},
        {"KHR_materials_clearcoat",
         {{"clearcoatFactor", 0.8},
          {"clearcoatRoughnessFactor", 0.5},
          {"clearcoatRoughnessTexture", {{"index", 0}}}}}};
    const MeshFile f =
        read({{"extensions", ext}, {"pbrMetallicRoughness", {{"metallicFactor", 0}}}},
             {{"extensionsUsed",
               {"KHR_materials_ior", "KHR_materials_transmission", "KHR_materials_volume",
                "KHR_materials_clearcoat"}}});
    EXPECT_TRUE(f.warnings.empty());
    const Bsdf b = make_bsdf(f.materials[0], vec2(0.75f, 0.5f), f.textures);
    EXPECT_NEAR(b.specular.g, 1.0f / 9.0f, 1e-6f);  // ((2 - 1) / (2 + 1))^2
    EXPECT_NEAR(b.transmit.g, 0.5f, 1e-6f);
    EXPECT_NEAR(b.absorption.r, std::log(2.0f) / 2.0f, 1e-6f);
    EXPECT_EQ(b.absorption.g, 0.0f);
    EXPECT_NEAR(b.coat, 0.8f, 1e-6f);
    // The roughness texture's green (128/255, linear) times its factor, squared.
    EXPECT_NEAR(b.coat_alpha, square(0.5f * 128.0f / 255.0f), 1e-6f);
    // No normal map of its own here.
    EXPECT_FALSE(std::get<CookTorranceMaterial>(f.materials[0].model).clearcoat_normal.present());
}

TEST_F(GltfTextures, SpecularStrengthIsTheTexturesAlphaAndItsColourTintsF0InSrgb) {
    // RGBA texels: left (255, 0, 0) alpha 0, right (0, 128, 255) alpha 200.
    const unsigned char texels[8] = {255, 0, 0, 0, 0, 128, 255, 200};
    ASSERT_NE(stbi_write_png((dir / "tex.png").c_str(), 2, 1, 4, texels, 8), 0);
    const json ext = {{"KHR_materials_specular",
                       {{"specularFactor", 0.5},
                        {"specularTexture", {{"index", 0}}},
                        {"specularColorFactor", {2.0, 1.0, 1.0}},
                        {"specularColorTexture", {{"index", 0}}}}}};
    const MeshFile f =
        read({{"extensions", ext}, {"pbrMetallicRoughness", {{"metallicFactor", 0}}}},
             {{"extensionsUsed", {"KHR_materials_specular"}}});
    EXPECT_TRUE(f.warnings.empty());
    // Right texel: strength 0.5 x 200/255; tint (2 x 0, 128 in sRGB, 1); F0 = 0.04 tint x
    // strength; F90 = strength.
    const Bsdf b = make_bsdf(f.materials[0], vec2(0.75f, 0.5f), f.textures);
    const float s = 0.5f * 200.0f / 255.0f;
    EXPECT_NEAR(b.f90, s, 1e-6f);
    EXPECT_NEAR(b.specular.r, 0.0f, 1e-7f);
    EXPECT_NEAR(b.specular.g, 0.04f * 0.2158605f * s, 1e-6f);
    EXPECT_NEAR(b.specular.b, 0.04f * s, 1e-6f);
    // Left texel: alpha 0, no specular at all: F = 0 at every angle, the diffuse part whole.
    const Bsdf left = make_bsdf(f.materials[0], vec2(0.25f, 0.5f), f.textures);
    EXPECT_EQ(left.f90, 0.0f);
    EXPECT_EQ(specular_fresnel(left, 0.1f), Color(0.0f));
    // Without the extension: F0 0.04, F90 1.
    const MeshFile dielectric = read({{"pbrMetallicRoughness", {{"metallicFactor", 0}}}});
    const Bsdf plain = make_bsdf(dielectric.materials[0], vec2(0.5f), dielectric.textures);
    EXPECT_NEAR(plain.specular.g, 0.04f, 1e-7f);
    EXPECT_EQ(plain.f90, 1.0f);
}

TEST_F(GltfTextures, TheClearcoatsNormalTextureIsItsOwnLinearWithItsScale) {
    const json ext = {
        {"KHR_materials_clearcoat",
         {{"clearcoatFactor", 1.0}, {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.25}}}}}};
    const MeshFile f = read({{"extensions", ext}, {"normalTexture", {{"index", 0}}}},
                            {{"extensionsUsed", {"KHR_materials_clearcoat"}}});
    const auto& ct = std::get<CookTorranceMaterial>(f.materials[0].model);
    ASSERT_TRUE(ct.clearcoat_normal.present());
    EXPECT_EQ(ct.clearcoat_normal.scale, 0.25f);
    EXPECT_NEAR(at(ct.clearcoat_normal.texture, vec2(0.75f, 0.5f), f).g, 128.0f / 255.0f,
                1e-6f);  // linear
    // The coat's normal from its own map, the base's from the base's: with scale 0.25 the
    // coat's is bent less; without a map of its own the coat takes the unmapped normal.
    const vec3 ns(0, 0, 1), ng(0, 0, 1);
    const vec4 tangent(1, 0, 0, 1);
    const Color texel(1.0f, 0.5f, 1.0f);  // a normal tilted toward +x
    const vec3 coat = coat_shading_normal(f.materials[0], texel, ns, ng, tangent);
    const vec3 base = mapped_normal(f.materials[0].normal_map, texel, ns, ng, tangent);
    EXPECT_GT(coat.z, base.z);
    EXPECT_GT(coat.x, 0.0f);
    Material no_own = f.materials[0];
    std::get<CookTorranceMaterial>(no_own.model).clearcoat_normal = NormalMap{};
    EXPECT_EQ(coat_shading_normal(no_own, texel, ns, ng, tangent), ns);
    Material no_maps = no_own;
    no_maps.normal_map = NormalMap{};
    EXPECT_EQ(coat_shading_normal(no_maps, texel, ns, ng, tangent), vec3(0.0f));  // takes ns
}

TEST_F(GltfTextures, ANetworkUriIsRefusedByName) {
    const json material = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    for (const json& extra :
         {json{{"images", {{{"uri", "https://example.com/tex.png"}}}}},
          json{{"buffers", {{{"byteLength", 44}, {"uri", "http://example.com/buf.bin"}}}}}}) {
        try {
            read(material, extra);
            ADD_FAILURE() << extra.dump() << " was read";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("example.com"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("names a network resource"), std::string::npos)
                << e.what();
        }
    }
}

TEST_F(GltfTextures, TextureTransformOffsetsRotatesAndScales) {
    // offset (0.5, 0): u = 0.25 reads u = 0.75, the right texel.
    json offset = {
        {"pbrMetallicRoughness",
         {{"baseColorTexture",
           {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}}}}}}}};
    MeshFile f = read(offset);
    auto base = [&](const MeshFile& m) {
        return std::get<CookTorranceMaterial>(m.materials[0].model).base_color;
    };
    EXPECT_NEAR(at(base(f), vec2(0.25f, 0.5f), f).b, 1.0f, 1e-6f);
    // rotation 90 degrees about glTF's origin (the image's top-left), then offset (0.5, 0):
    // glTF's (u, v) = (0.3, 0.2) (svetlo's (0.3, 0.8)) turns to (0.2, -0.3), offset to
    // (0.7, -0.3): the right texel. The opposite turn, (-0.2, 0.3), would read u = 0.3: the
    // left one (TextureTransformTest's red marker).
    json rotate = offset;
    rotate["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = {
        {"rotation", 1.5707963}, {"offset", {0.5, 0}}};
    f = read(rotate);
    EXPECT_NEAR(at(base(f), vec2(0.3f, 0.8f), f).b, 1.0f, 1e-6f);
    EXPECT_EQ(at(base(f), vec2(0.3f, 0.8f), f).r, 0.0f);
    json scale = offset;
    scale["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = {
        {"scale", {0.25, 1}}};
    f = read(scale);
    EXPECT_NEAR(at(base(f), vec2(0.9f, 0.5f), f).r, 1.0f, 1e-6f);  // 0.9 reads 0.225: left
}

TEST_F(GltfTextures, AMissingOrUndecodableImageNamesTheMaterial) {
    const json material = {{"name", "visor"},
                           {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    std::ofstream(dir / "broken.png") << "not a png";
    for (const char* uri : {"missing.png", "broken.png"}) {
        try {
            read(material, {{"images", {{{"uri", uri}}}}});
            ADD_FAILURE() << uri << " was read";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find(uri), std::string::npos) << e.what();
        }
    }
    try {
        read({{"name", "visor"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}});
        ADD_FAILURE() << "texture 3 was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(
            std::string(e.what()).find("material 'visor' baseColorTexture: texture 3 missing"),
            std::string::npos)
            << e.what();
    }
}

/// RFC 4648's base64 digits.
const std::string kBase64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// RFC 4648 base64 of `bytes`.
std::string base64(const std::string& bytes) {
    std::string out;
    for (size_t k = 0; k < bytes.size(); k += 3) {
        const size_t n = std::min<size_t>(3, bytes.size() - k);
        uint32_t v = 0;
        for (size_t b = 0; b < 3; ++b)
            v = (v << 8) | (b < n ? static_cast<unsigned char>(bytes[k + b]) : 0u);
        for (size_t d = 0; d < 4; ++d) out += d <= n ? kBase64[(v >> (18 - 6 * d)) & 63] : '=';
    }
    return out;
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

// An image file is read by the thread that decodes it, not by tinygltf (gltf_reader.cpp):
// its texels are those of the same image written into the glTF.
TEST_F(GltfTextures, AnImageFileGivesTheTexelsOfTheSameImageInADataUri) {
    const json material = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    const MeshFile from_file = read(material);
    const std::string uri = "data:image/png;base64," + base64(file_bytes(dir / "tex.png"));
    const MeshFile from_uri = read(material, {{"images", {{{"uri", uri}}}}});
    ASSERT_EQ(from_file.textures.size(), 1u);
    ASSERT_EQ(from_uri.textures.size(), 1u);
    EXPECT_TRUE(from_file.textures[0].same_texels(from_uri.textures[0]));
    EXPECT_EQ(from_file.textures[0].width(), 2);
}

// A buffer whose file begins as a PNG does (legal, if odd) is read as the buffer it is, and
// the model's image files still decode.
TEST_F(GltfTextures, ABufferFileThatBeginsAsAnImageIsReadAsABuffer) {
    std::ifstream in(fs::path(SVETLO_TEST_DATA) / "triangle.gltf");
    const json triangle = json::parse(in);
    const std::string data = triangle["buffers"][0]["uri"];
    std::string buffer = file_bytes(dir / "tex.png").substr(0, 8);  // the PNG signature
    // The triangle's 44 bytes, decoded from its data URI.
    uint32_t bits = 0;
    int count = 0;
    for (char c : data.substr(data.find(',') + 1)) {
        if (c == '=') break;
        bits = (bits << 6) | static_cast<uint32_t>(kBase64.find(c));
        if ((count += 6) >= 8) buffer += static_cast<char>((bits >> (count -= 8)) & 0xFF);
    }
    ASSERT_EQ(buffer.size(), 8u + 44u);
    std::ofstream(dir / "geometry.png", std::ios::binary) << buffer;
    const MeshFile f = read({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
                            {{"buffers", {{{"uri", "geometry.png"}, {"byteLength", 52}}}},
                             {"bufferViews",
                              {{{"buffer", 0}, {"byteOffset", 8}, {"byteLength", 36}},
                               {{"buffer", 0}, {"byteOffset", 44}, {"byteLength", 6}}}}});
    ASSERT_EQ(f.mesh.positions.size(), 3u);
    EXPECT_EQ(f.mesh.positions[1], vec3(1.0f, 0.0f, -1.0f));  // node 0 moves it to z = -1
    ASSERT_EQ(f.textures.size(), 1u);
    EXPECT_EQ(f.textures[0].width(), 2);
}

}  // namespace
}  // namespace svetlo

namespace svetlo {
namespace {

// OBJ/MTL texture maps (docs/scene-format.md, "Mesh files"): map_Kd replaces Kd (sRGB),
// map_Ke is scaled by Ke, Pr and Pm make a cook_torrance material; a map that is not there
// names the material and the map.
TEST(ObjTextures, MapsReplaceTheirColoursAndPbrKeysMakeCookTorrance) {
    const fs::path dir = fs::temp_directory_path() / "svetlo_obj_textures";
    fs::create_directories(dir);
    Image im(2, 1);
    im.at(0, 0) = Color(1.0f, 0.0f, 0.0f);
    im.at(1, 0) = Color(0.0f, 0.0f, 1.0f);
    write_image(dir / "tex.png", im, PixelMeaning::Data, 1.0f, "test");
    std::ofstream(dir / "m.mtl") << "newmtl painted\nKd 0.2 0.2 0.2\nmap_Kd tex.png\n"
                                    "newmtl lamp\nKe 2 2 2\nmap_Ke tex.png\n"
                                    "newmtl metal\nKd 0.9 0.8 0.7\nPr 0.25\nPm 1\n";
    const std::string faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvt 0.25 0.5\nvt 0.25 0.5\n";
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\n"
                                 << faces << "usemtl painted\nf 1/1 2/2 3/3\n"
                                 << "usemtl lamp\nf 1/1 2/2 3/3\nusemtl metal\nf 1/1 2/2 3/3\n";
    const MeshFile f = read_mesh_file(dir / "m.obj");
    ASSERT_EQ(f.materials.size(), 3u);
    const Bsdf painted = make_bsdf(f.materials[0], vec2(0.25f, 0.5f), f.textures);
    EXPECT_NEAR(painted.diffuse.r, 1.0f, 1e-6f);  // the map's red, not Kd's grey
    EXPECT_EQ(painted.diffuse.b, 0.0f);
    const Bsdf lamp = make_bsdf(f.materials[1], vec2(0.75f, 0.5f), f.textures);
    EXPECT_NEAR(lamp.emission.b, 2.0f, 1e-6f);  // the map's blue times Ke
    EXPECT_EQ(lamp.emission.r, 0.0f);
    const auto* metal = std::get_if<CookTorranceMaterial>(&f.materials[2].model);
    ASSERT_NE(metal, nullptr);
    EXPECT_FLOAT_EQ(metal->roughness, 0.25f);
    EXPECT_FLOAT_EQ(metal->metallic, 1.0f);
    EXPECT_EQ(f.textures.size(), 1u);  // one file, one colour space: read once
    std::ofstream(dir / "m.mtl") << "newmtl painted\nmap_Kd nowhere.png\n";
    try {
        read_mesh_file(dir / "m.obj");
        ADD_FAILURE() << "a missing map was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("material 'painted' map_Kd 'nowhere.png'"),
                  std::string::npos)
            << e.what();
    }
    fs::remove_all(dir);
}

// map_Pr and map_Pm replace Pr and Pm, as glTF's metallic-roughness channels (G, B); map_Ns
// multiplies Ns.
TEST(ObjTextures, ScalarMapsMakeRoughnessMetallicAndShininess) {
    const fs::path dir = fs::temp_directory_path() / "svetlo_obj_scalar_maps";
    fs::create_directories(dir);
    Image ramp(2, 1);  // linear codes: 0.2 on the left, 0.6 on the right (first channel)
    ramp.at(0, 0) = Color(0.2f);
    ramp.at(1, 0) = Color(0.6f);
    write_image(dir / "ramp.pfm", ramp, PixelMeaning::Radiance, 1.0f, "test");
    write_image(dir / "half.pfm", Image(1, 1, Color(0.5f)), PixelMeaning::Radiance, 1.0f, "test");
    std::ofstream(dir / "m.mtl")
        << "newmtl rough\nKd 0.5 0.5 0.5\nmap_Pr ramp.pfm\nPm 0.3\n"
           "newmtl both\nKd 0.5 0.5 0.5\nmap_Pr half.pfm\nmap_Pm ramp.pfm\n"
           "newmtl shiny\nKd 0.5 0.5 0.5\nKs 0.5 0.5 0.5\nNs 100\n"
           "map_Ns ramp.pfm\n";
    const std::string faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\n"
                                 << faces << "usemtl rough\nf 1/1 2/2 3/3\n"
                                 << "usemtl both\nf 1/1 2/2 3/3\nusemtl shiny\nf 1/1 2/2 3/3\n";
    const MeshFile f = read_mesh_file(dir / "m.obj");
    ASSERT_EQ(f.materials.size(), 3u);
    const vec2 left(0.25f, 0.5f), right(0.75f, 0.5f);
    const Bsdf rough = make_bsdf(f.materials[0], right, f.textures);
    EXPECT_NEAR(rough.alpha, square(0.6f), 1e-6f);  // the map's roughness, not a factor's
    EXPECT_NEAR(rough.specular.r, glm::mix(0.04f, 0.5f, 0.3f), 1e-6f);  // Pm 0.3 kept
    const Bsdf both_left = make_bsdf(f.materials[1], left, f.textures);
    const Bsdf both_right = make_bsdf(f.materials[1], right, f.textures);
    EXPECT_NEAR(both_left.alpha, square(0.5f), 1e-6f);  // the 1 x 1 map read everywhere
    EXPECT_NEAR(both_left.specular.r, glm::mix(0.04f, 0.5f, 0.2f), 1e-6f);
    EXPECT_NEAR(both_right.specular.r, glm::mix(0.04f, 0.5f, 0.6f), 1e-6f);
    EXPECT_NEAR(make_bsdf(f.materials[2], left, f.textures).shininess, 20.0f, 1e-4f);
    EXPECT_NEAR(make_bsdf(f.materials[2], right, f.textures).shininess, 60.0f, 1e-4f);
    fs::remove_all(dir);
}

TEST(ObjTextures, NormIsANormalMapMapBumpAHeightMapMadeIntoOneAndMapDAMask) {
    const fs::path dir = fs::temp_directory_path() / "svetlo_obj_normal_maps";
    fs::create_directories(dir);
    // Heights rising 0.1 a texel to the right (i), flat up the image: a slope of 0.1 times
    // -bm 2, so the normal (-0.2, 0, 1), normalised, wherever the ramp does not wrap.
    Image heights(8, 4);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 8; ++i) heights.at(i, j) = Color(0.1f * static_cast<float>(i));
    write_image(dir / "h.pfm", heights, PixelMeaning::Radiance, 1.0f, "test");
    write_image(dir / "n.pfm", Image(2, 2, Color(0.5f, 0.75f, 1.0f)), PixelMeaning::Radiance, 1.0f,
                "test");
    std::ofstream(dir / "m.mtl") << "newmtl bumpy\nKd 0.5 0.5 0.5\nmap_Bump -bm 2 h.pfm\n"
                                    "newmtl mapped\nKd 0.5 0.5 0.5\nnorm n.pfm\n"
                                    "newmtl plain\nKd 0.5 0.5 0.5\n"
                                    "newmtl cut\nKd 0.5 0.5 0.5\nmap_d h.pfm\n";
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    "usemtl bumpy\nf 1 2 3\nusemtl mapped\nf 1 2 3\n"
                                    "usemtl plain\nf 1 2 3\nusemtl cut\nf 1 2 3\n";
    const MeshFile f = read_mesh_file(dir / "m.obj");
    ASSERT_EQ(f.materials.size(), 4u);
    // map_d: a mask of the map's coverage (a float map's red channel), the heights here.
    const Alpha& cut = f.materials[3].alpha;
    EXPECT_EQ(cut.mode, AlphaMode::Mask);
    EXPECT_NEAR(eval_color(cut.coverage, vec2(2.5f / 8.0f, 0.5f), f.textures).r, 0.2f, 1e-6f);
    EXPECT_FALSE(f.materials[2].alpha.active());
    const NormalMap& bumpy = f.materials[0].normal_map;
    ASSERT_TRUE(bumpy.present());
    const vec3 n = glm::normalize(vec3(-0.2f, 0.0f, 1.0f));
    const Color texel = eval_color(bumpy.texture, vec2(4.5f / 8.0f, 0.5f), f.textures);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(texel[c], 0.5f * (n[c] + 1.0f), 1e-5f) << c;
    ASSERT_TRUE(f.materials[1].normal_map.present());
    EXPECT_NEAR(eval_color(f.materials[1].normal_map.texture, vec2(0.5f), f.textures).g, 0.75f,
                1e-6f);
    EXPECT_FALSE(f.materials[2].normal_map.present());
    fs::remove_all(dir);
}

}  // namespace
}  // namespace svetlo
