#include "svetlo/scene/mesh_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "svetlo/core/error.h"
#include "svetlo/scene/file_cache.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;

fs::path data(const std::string& name) { return fs::path(SVETLO_TEST_DATA) / name; }

TEST(Obj, CornellBoxMapsMtlOntoMaterials) {
    MeshFile f = read_mesh_file(fs::path(SVETLO_SCENE_MODELS) / "CornellBox-Original.obj");
    EXPECT_GT(f.mesh.triangle_count(), 30u);
    ASSERT_EQ(f.mesh.face_material.size(), f.mesh.triangle_count());
    int emissive = 0, phong = 0;
    for (size_t k = 0; k < f.materials.size(); ++k) {
        if (const auto* e = std::get_if<EmissiveMaterial>(&f.materials[k].model)) {
            EXPECT_EQ(f.material_names[k], "light");
            EXPECT_EQ(e->radiance.value, Color(17, 12, 4));  // Ke
            EXPECT_NEAR(e->albedo.value.r, 0.78f, 1e-6f);    // Kd
            ++emissive;
        } else if (const auto* p = std::get_if<PhongMaterial>(&f.materials[k].model)) {
            if (f.material_names[k] == "leftWall") {
                EXPECT_EQ(p->kd.value, Color(0.63f, 0.065f, 0.05f));
            }
            ++phong;
        }
    }
    EXPECT_EQ(emissive, 1);
    EXPECT_EQ(phong, 7);
}

TEST(Ply, BunnyLoads) {
    MeshFile f = read_mesh_file(data("bun_zipper_res4.ply"));
    EXPECT_EQ(f.mesh.positions.size(), 453u);
    EXPECT_EQ(f.mesh.triangle_count(), 948u);
}

TEST(Ply, AsciiAndBinaryAgree) {
    MeshFile a = read_mesh_file(data("quad_ascii.ply"));
    MeshFile b = read_mesh_file(data("quad_binary.ply"));
    ASSERT_EQ(a.mesh.positions.size(), 4u);
    EXPECT_EQ(a.mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));  // fanned quad
    EXPECT_EQ(a.mesh.positions, b.mesh.positions);
    EXPECT_EQ(a.mesh.indices, b.mesh.indices);
}

TEST(Gltf, TriangleWithMaterialAndLight) {
    MeshFile f = read_mesh_file(data("triangle.gltf"));
    ASSERT_EQ(f.mesh.triangle_count(), 1u);
    // The node translates by (0, 0, -1).
    EXPECT_EQ(f.mesh.positions[1], vec3(1, 0, -1));
    ASSERT_EQ(f.materials.size(), 1u);
    const auto& ct = std::get<CookTorranceMaterial>(f.materials[0].model);
    EXPECT_FLOAT_EQ(ct.roughness, 0.25f);
    EXPECT_FLOAT_EQ(ct.metallic, 1.0f);
    ASSERT_EQ(f.lights.size(), 1u);
    EXPECT_EQ(std::get<PointLight>(f.lights[0]).position, vec3(0, 2, 0));
}

TEST(MeshFiles, MalformedFilesAreErrors) {
    for (const char* name : {"broken.ply", "lying_header.ply", "bad_index.obj", "broken.gltf",
                             "missing.obj", "not_a_mesh.txt"}) {
        EXPECT_THROW(read_mesh_file(data(name)), std::runtime_error) << name;
    }
}

TEST(MeshFiles, TheCacheReadsAFileOnceUntilItChanges) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("svetlo_meshes_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path obj = dir / "tri.obj";
    { std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"; }
    FileCache cache;
    const auto first = cache.read(obj);
    EXPECT_EQ(cache.read(dir / "." / "tri.obj"), first);  // the same file, another spelling
    EXPECT_EQ(first->mesh.positions.size(), 3u);
    // Edited: two triangles now, and a later time.
    { std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n"; }
    fs::last_write_time(obj, fs::last_write_time(obj) + std::chrono::seconds(2));
    const auto second = cache.read(obj);
    EXPECT_NE(second, first);
    EXPECT_EQ(second->mesh.indices.size(), 6u);
    EXPECT_EQ(first->mesh.indices.size(), 3u);  // what a render holds stays as it was read
    fs::remove(obj);
    EXPECT_THROW(cache.read(obj), std::runtime_error);  // gone: not the old copy
    fs::remove_all(dir);
}

// svetlo serve reads a scene's environment once, not at every request.
TEST(MeshFiles, TheCacheReadsAnImageOnceUntilItChanges) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("svetlo_images_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path pfm = dir / "sky.pfm";
    Image sky(4, 2, Color(0.5f));
    write_image(pfm, sky, PixelMeaning::Radiance, 1.0f, "test");
    FileCache cache;
    const auto read = [&] {
        return cache.read_texture(pfm, TexelMeaning::Linear, kMaxTextureBytes, "environment",
                                  NegativeTexels::ClampToZero);
    };
    const fs::file_time_type time = fs::last_write_time(pfm);
    EXPECT_EQ(read().texel(0, 0), Color(0.5f));
    // The same size and time, other texels: the copy read before is what the cache holds.
    write_image(pfm, Image(4, 2, Color(2.0f)), PixelMeaning::Radiance, 1.0f, "test");
    fs::last_write_time(pfm, time);
    EXPECT_EQ(read().texel(0, 0), Color(0.5f));
    // A later time: read again.
    fs::last_write_time(pfm, time + std::chrono::seconds(2));
    EXPECT_EQ(read().texel(0, 0), Color(2.0f));
    // Less memory left than the texture takes: refused as read_texture refuses it.
    EXPECT_THROW(cache.read_texture(pfm, TexelMeaning::Linear, 16, "environment",
                                    NegativeTexels::ClampToZero),
                 Error);
    fs::remove_all(dir);
}

// The scenes of one command (svetlo serve's requests) read a material's texture and the
// environment once, through the cache they are given.
TEST(MeshFiles, ScenesReadTheirTexturesAndEnvironmentThroughTheCache) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("svetlo_scene_images_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const nlohmann::json j = {
        {"camera", {{"position", {0, 0, 3}}, {"look_at", {0, 0, 0}}}},
        {"materials", {{"m", {{"type", "lambert"}, {"albedo", {{"texture", "wood.pfm"}}}}}}},
        {"environment", {{"file", "sky.pfm"}}},
        {"objects",
         {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}}}}};
    for (const char* name : {"wood.pfm", "sky.pfm"})
        write_image(dir / name, Image(4, 2, Color(0.5f)), PixelMeaning::Radiance, 1.0f, "test");
    FileCache cache;
    const auto texels = [&] {
        const Scene scene = scene_from_json(j, dir / "s.json", &cache);
        EXPECT_EQ(scene.textures.size(), 2u);
        return std::pair{scene.textures[0].texel(0, 0).r, scene.textures[1].texel(0, 0).r};
    };
    EXPECT_EQ(texels(), std::pair(0.5f, 0.5f));
    // Other texels with the same size and time: the cache's copies are what the scene gets.
    for (const char* name : {"wood.pfm", "sky.pfm"}) {
        const fs::file_time_type time = fs::last_write_time(dir / name);
        write_image(dir / name, Image(4, 2, Color(2.0f)), PixelMeaning::Radiance, 1.0f, "test");
        fs::last_write_time(dir / name, time);
    }
    EXPECT_EQ(texels(), std::pair(0.5f, 0.5f));
    for (const char* name : {"wood.pfm", "sky.pfm"})
        fs::last_write_time(dir / name, fs::last_write_time(dir / name) + std::chrono::seconds(2));
    EXPECT_EQ(texels(), std::pair(2.0f, 2.0f));  // changed files are read again
    fs::remove_all(dir);
}

TEST(MeshFiles, SmoothNormalsAreAreaWeighted) {
    Mesh m;
    m.positions = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1)};
    m.indices = {0, 1, 2, 0, 3, 1};  // faces with normals +z and +y
    compute_vertex_normals(m);
    EXPECT_NEAR(glm::dot(m.normals[0], glm::normalize(vec3(0, 1, 1))), 1.0f, 1e-6f);
    EXPECT_NEAR(m.normals[2].z, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace svetlo
