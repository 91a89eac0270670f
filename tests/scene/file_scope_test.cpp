// The served folder's rule (FileScope; docs/viewer.md, "What the server reads"): every file a
// scene names, and every file a mesh file names in turn, lies inside the folder, links
// followed; the command line's scope is anywhere.
#include "svetlo/core/file_scope.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "svetlo/core/error.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;

/// A folder of its own under the system's temporary one: `served/` with a scene's files in
/// it, and files beside it that a served scene must not reach.
class Folders : public ::testing::Test {
protected:
    void SetUp() override {
        root = fs::temp_directory_path() /
               ("svetlo_scope_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(root);
        fs::create_directories(root / "served" / "models");
        write(root / "outside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        write(root / "served" / "models" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        write(root / "outside.mtl", "newmtl red\nKd 1 0 0\n");
        write(root / "served" / "up.obj",
              "mtllib ../outside.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
        // A glTF whose buffer lies outside: three positions, 36 bytes.
        std::ofstream(root / "outside.bin", std::ios::binary)
            .write(std::string(36, '\0').data(), 36);
        write(root / "served" / "up.gltf",
              R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
          "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
          "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
          "bufferViews": [{"buffer": 0, "byteLength": 36}],
          "buffers": [{"uri": "../outside.bin", "byteLength": 36}]})");
        fs::create_symlink(root / "outside.obj", root / "served" / "link.obj");
    }
    void TearDown() override { fs::remove_all(root); }
    static void write(const fs::path& path, const std::string& text) {
        std::ofstream(path) << text;
    }

    fs::path root;
};

TEST_F(Folders, InsideResolvesOutsideIsRefused) {
    const FileScope scope(root / "served");
    const fs::path base = root / "served";
    EXPECT_EQ(scope.resolve(base, "models/tri.obj"), fs::canonical(base / "models" / "tri.obj"));
    EXPECT_EQ(scope.resolve(base / "models", "../models/tri.obj"),
              fs::canonical(base / "models" / "tri.obj"));
    for (const std::string& name :
         std::vector<std::string>{"../outside.obj", (root / "outside.obj").string(), "link.obj",
                                  "models/../../outside.obj", "/etc/passwd"}) {
        try {
            scope.resolve(base, name);
            ADD_FAILURE() << name << " resolved";
        } catch (const std::runtime_error& e) {
            EXPECT_EQ(std::string(e.what()), "'" + name + "' is outside the served folder");
        }
    }
}

TEST_F(Folders, TheCommandLinesScopeIsAnywhere) {
    const FileScope anywhere;
    EXPECT_FALSE(anywhere.confined());
    EXPECT_EQ(anywhere.resolve(root / "served", "../outside.obj"),
              root / "served" / "../outside.obj");
    EXPECT_NO_THROW(read_mesh_file(root / "served" / "up.gltf"));
    EXPECT_NO_THROW(read_mesh_file(root / "served" / "up.obj"));
}

TEST_F(Folders, MessagesNameFilesRelativeToTheFolder) {
    const FileScope scope(root / "served");
    const std::string folder = fs::canonical(root / "served").string();
    EXPECT_EQ(scope.relative_text(folder + "/a.json: objects[0].file: bad"),
              "a.json: objects[0].file: bad");
    EXPECT_EQ(FileScope().relative_text(folder + "/a.json"), folder + "/a.json");
}

TEST_F(Folders, AMeshFilesOwnReferencesStayInside) {
    const FileScope scope(root / "served");
    EXPECT_THROW(read_mesh_file(root / "served" / "up.gltf", scope), std::runtime_error);
    try {
        read_mesh_file(root / "served" / "up.obj", scope);
        ADD_FAILURE() << "the MTL outside was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("outside the served folder"), std::string::npos)
            << e.what();
    }
    EXPECT_NO_THROW(read_mesh_file(root / "served" / "models" / "tri.obj", scope));
}

TEST_F(Folders, AScenesFilesAndOverridesStayInside) {
    const fs::path scene = root / "served" / "s.json";
    auto load = [&](const std::string& file) {
        nlohmann::json j = {{"camera", {{"position", {0, 0, 3}}, {"look_at", {0, 0, 0}}}},
                            {"materials", {{"m", {{"type", "lambert"}}}}},
                            {"objects", {{{"type", "mesh"}, {"file", file}, {"material", "m"}}}}};
        return scene_from_json(j, scene, nullptr, FileScope(root / "served"));
    };
    EXPECT_NO_THROW(load("models/tri.obj"));
    for (const std::string& file : std::vector<std::string>{
             "../outside.obj", (root / "outside.obj").string(), "link.obj", "up.gltf"}) {
        try {
            load(file);
            ADD_FAILURE() << file << " loaded";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "objects[0].file") << e.what();
            EXPECT_NE(e.message().find("outside the served folder"), std::string::npos) << e.what();
        }
    }
    nlohmann::json textured = {
        {"camera", {{"position", {0, 0, 3}}, {"look_at", {0, 0, 0}}}},
        {"materials", {{"m", {{"type", "lambert"}, {"albedo", {{"texture", "../outside.png"}}}}}}},
        {"objects",
         {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}}}}};
    try {
        scene_from_json(textured, scene, nullptr, FileScope(root / "served"));
        ADD_FAILURE() << "a texture outside was named";
    } catch (const Error& e) {
        EXPECT_EQ(e.what(), scene.string() +
                                ": materials.m.albedo.texture: '../outside.png' is "
                                "outside the served folder");
    }
}

}  // namespace
}  // namespace svetlo
