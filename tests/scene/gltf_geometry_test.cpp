// glTF geometry as the specification lays it out (docs/scene-format.md, "Mesh files"): sparse
// accessors, triangle strips and fans, morph targets at their default weights, skins at the
// nodes' pose, the first animation's first keys, EXT_mesh_gpu_instancing, the node trees, and
// flat primitives (without NORMAL) beside smooth ones.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "svetlo/core/error.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene_loader.h"
#include "svetlo/scene/tangents.h"

namespace svetlo {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A glTF written from parts: one buffer (a .bin file) that views and accessors are appended
/// to, and the rest of the JSON given by the test.
class GltfWriter {
public:
    /// A buffer view of `values` (floats or integers of type T), its index.
    template <typename T>
    int view(const std::vector<T>& values) {
        while (bytes_.size() % 4 != 0) bytes_.push_back(0);
        const size_t offset = bytes_.size();
        bytes_.resize(offset + values.size() * sizeof(T));
        std::memcpy(bytes_.data() + offset, values.data(), values.size() * sizeof(T));
        views_.push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
        return static_cast<int>(views_.size()) - 1;
    }
    /// An accessor (`fields` given whole), its index.
    int accessor(const json& fields) {
        accessors_.push_back(fields);
        return static_cast<int>(accessors_.size()) - 1;
    }
    /// A VEC3 float accessor of `values` in a view of its own.
    int vec3s(const std::vector<float>& values) {
        return accessor({{"bufferView", view(values)},
                         {"componentType", 5126},
                         {"count", values.size() / 3},
                         {"type", "VEC3"}});
    }
    /// An unsigned short index accessor.
    int indices(const std::vector<uint16_t>& values) {
        return accessor({{"bufferView", view(values)},
                         {"componentType", 5123},
                         {"count", values.size()},
                         {"type", "SCALAR"}});
    }
    /// Writes NAME.gltf and NAME.bin with `rest` (meshes, nodes...) and one scene of
    /// `nodes`; its path.
    fs::path write(const std::string& name, json rest, const json& nodes = {0}) {
        const fs::path dir = fs::temp_directory_path() / "svetlo_gltf_geometry";
        fs::create_directories(dir);
        std::ofstream(dir / (name + ".bin"), std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes_.data()),
                   static_cast<std::streamsize>(bytes_.size()));
        rest["asset"] = {{"version", "2.0"}};
        rest["buffers"] = {{{"uri", name + ".bin"}, {"byteLength", bytes_.size()}}};
        rest["bufferViews"] = views_;
        rest["accessors"] = accessors_;
        rest["scene"] = 0;
        rest["scenes"] = {{{"nodes", nodes}}};
        std::ofstream(dir / (name + ".gltf")) << rest.dump();
        return dir / (name + ".gltf");
    }

private:
    std::vector<unsigned char> bytes_;
    json views_ = json::array(), accessors_ = json::array();
};

/// One primitive of `attributes` (and `extra` fields: indices, mode, targets).
json one_mesh(const json& attributes, const json& extra = json::object()) {
    json prim = {{"attributes", attributes}};
    prim.update(extra);
    return {{{"primitives", {prim}}}};
}

/// The (unit) geometric normal of triangle t.
vec3 face_normal(const Mesh& m, size_t t) {
    const vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
               c = m.positions[m.indices[3 * t + 2]];
    return glm::normalize(glm::cross(b - a, c - a));
}

// Five vertices in z = 0.
const std::vector<float> kZigZag = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};

TEST(GltfGeometry, ATriangleStripAlternatesItsWindingAsTheSpecificationSays) {
    // Vertices in the strip's order: 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1), 4 (0,2): every
    // triangle counter-clockwise seen from +z once the odd ones are turned.
    GltfWriter w;
    const int pos = w.vec3s(kZigZag);
    const MeshFile f =
        read_mesh_file(w.write("strip", {{"meshes", one_mesh({{"POSITION", pos}}, {{"mode", 5}})},
                                         {"nodes", {{{"mesh", 0}}}}}));
    ASSERT_EQ(f.mesh.triangle_count(), 3u);
    const std::vector<uint32_t> expected = {0, 1, 2, 1, 3, 2, 2, 3, 4};
    EXPECT_EQ(f.mesh.indices, expected);
    for (size_t t = 0; t < 3; ++t) EXPECT_GT(face_normal(f.mesh, t).z, 0.99f) << t;
}

TEST(GltfGeometry, ATriangleFanTurnsAboutItsFirstVertex) {
    GltfWriter w;
    // A square's corners and its centre first: 0 centre, then 1..5 counter-clockwise from
    // +z (the last closing the fan).
    const int pos = w.vec3s({0, 0, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, -1, -1, 0});
    const int idx = w.indices({0, 1, 2, 3, 4, 1});
    const MeshFile f = read_mesh_file(
        w.write("fan", {{"meshes", one_mesh({{"POSITION", pos}}, {{"indices", idx}, {"mode", 6}})},
                        {"nodes", {{{"mesh", 0}}}}}));
    ASSERT_EQ(f.mesh.triangle_count(), 4u);
    const std::vector<uint32_t> expected = {1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 0};
    EXPECT_EQ(f.mesh.indices, expected);
    for (size_t t = 0; t < 4; ++t) EXPECT_GT(face_normal(f.mesh, t).z, 0.99f) << t;
}

TEST(GltfGeometry, PointsAndLinesAreSkippedBesideTriangles) {
    GltfWriter w;
    const int pos = w.vec3s(kZigZag);
    json mesh = {{{"primitives",
                   {{{"attributes", {{"POSITION", pos}}}, {"mode", 0}},
                    {{"attributes", {{"POSITION", pos}}}, {"mode", 3}},
                    {{"attributes", {{"POSITION", pos}}}, {"mode", 6}}}}}};
    const MeshFile f =
        read_mesh_file(w.write("modes", {{"meshes", mesh}, {"nodes", {{{"mesh", 0}}}}}));
    EXPECT_EQ(f.mesh.triangle_count(), 3u);  // the fan's only
}

TEST(GltfGeometry, SparseValuesReplaceTheirElements) {
    GltfWriter w;
    w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0, 9, 9, 9});  // view 0
    const int at = w.view(std::vector<uint16_t>{1, 3});
    const int values = w.view(std::vector<float>{2, 0, 0, 1, 1, 0});
    json sparse = {{"count", 2},
                   {"indices", {{"bufferView", at}, {"componentType", 5123}}},
                   {"values", {{"bufferView", values}}}};
    const int moved = w.accessor({{"bufferView", 0},
                                  {"componentType", 5126},
                                  {"count", 4},
                                  {"type", "VEC3"},
                                  {"sparse", sparse}});
    // Without a buffer view: zeros, then the sparse values.
    const int zeros =
        w.accessor({{"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"sparse", sparse}});
    const int idx = w.indices({0, 1, 2, 0, 2, 3});
    json mesh = {{{"primitives",
                   {{{"attributes", {{"POSITION", moved}}}, {"indices", idx}},
                    {{"attributes", {{"POSITION", zeros}}}, {"indices", idx}}}}}};
    const MeshFile f =
        read_mesh_file(w.write("sparse", {{"meshes", mesh}, {"nodes", {{{"mesh", 0}}}}}));
    ASSERT_EQ(f.mesh.positions.size(), 8u);
    const std::vector<vec3> expected = {vec3(0, 0, 0), vec3(2, 0, 0), vec3(0, 1, 0), vec3(1, 1, 0),
                                        vec3(0, 0, 0), vec3(2, 0, 0), vec3(0, 0, 0), vec3(1, 1, 0)};
    for (size_t k = 0; k < 8; ++k) EXPECT_EQ(f.mesh.positions[k], expected[k]) << k;
}

TEST(GltfGeometry, BadSparseAccessorsAreRefusedWithOneLine) {
    struct Case {
        const char* name;
        json sparse_change;
        json accessor_change;
        const char* says;
    };
    const Case cases[] = {
        {"index_past_count",
         {{"indices", {{"bufferView", 1}, {"componentType", 5123}}}},
         json::object(),
         "sparse index out of range"},
        {"more_than_count", {{"count", 5}}, json::object(), "sparse count"},
        {"float_indices",
         {{"indices", {{"bufferView", 1}, {"componentType", 5126}}}},
         json::object(),
         "index type"},
        {"huge_without_view", json::object(), {{"count", 100000000}}, "without a buffer view"},
        {"values_past_buffer", {{"count", 4}}, {{"count", 4}}, "runs past"},
    };
    for (const Case& c : cases) {
        GltfWriter w;
        const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});  // view 0
        w.view(std::vector<uint16_t>{0, 7});                   // view 1: 7 is past count 3
        const int at = w.view(std::vector<uint16_t>{0, 1});
        const int values = w.view(std::vector<float>{1, 1, 1, 2, 2, 2});
        json sparse = {{"count", 2},
                       {"indices", {{"bufferView", at}, {"componentType", 5123}}},
                       {"values", {{"bufferView", values}}}};
        sparse.update(c.sparse_change);
        json fields = {{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}, {"sparse", sparse}};
        if (c.accessor_change.empty()) fields["bufferView"] = pos;
        fields.update(c.accessor_change);
        const int a = w.accessor(fields);
        const fs::path file =
            w.write(c.name, {{"meshes", one_mesh({{"POSITION", a}})}, {"nodes", {{{"mesh", 0}}}}});
        try {
            read_mesh_file(file);
            ADD_FAILURE() << c.name << " was read";
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(c.says), std::string::npos) << c.name << ": " << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << c.name << ": " << what;
        }
    }
}

/// A unit square in z = 0 with normals +z and a morph target that lifts vertex 2 by 1 along
/// z (a sparse target) and tilts the normals by (1, 0, 0); `mesh_weights` the mesh's own,
/// `nodes` the scene's nodes.
fs::path morphed_square(const std::string& name, const json& mesh_weights, const json& nodes) {
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    const int nor = w.vec3s({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    const int at = w.view(std::vector<uint16_t>{2});
    const int lift = w.view(std::vector<float>{0, 0, 1});
    const int dpos = w.accessor({{"componentType", 5126},
                                 {"count", 4},
                                 {"type", "VEC3"},
                                 {"sparse",
                                  {{"count", 1},
                                   {"indices", {{"bufferView", at}, {"componentType", 5123}}},
                                   {"values", {{"bufferView", lift}}}}}});
    const int dnor = w.vec3s({1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0});
    const int idx = w.indices({0, 1, 2, 0, 2, 3});
    json mesh = one_mesh({{"POSITION", pos}, {"NORMAL", nor}},
                         {{"indices", idx}, {"targets", {{{"POSITION", dpos}, {"NORMAL", dnor}}}}});
    if (!mesh_weights.is_null()) mesh[0]["weights"] = mesh_weights;
    json scene_nodes = json::array();
    for (size_t k = 0; k < nodes.size(); ++k) scene_nodes.push_back(static_cast<int>(k));
    return w.write(name, {{"meshes", mesh}, {"nodes", nodes}}, scene_nodes);
}

TEST(GltfGeometry, MorphTargetsMoveVerticesAndNormalsByTheirDefaultWeights) {
    const MeshFile f = read_mesh_file(morphed_square("morph", {0.5}, {{{"mesh", 0}}}));
    ASSERT_EQ(f.mesh.positions.size(), 4u);
    EXPECT_EQ(f.mesh.positions[2], vec3(1, 1, 0.5f));
    EXPECT_EQ(f.mesh.positions[3], vec3(0, 1, 0));
    const vec3 n = glm::normalize(vec3(0.5f, 0, 1));
    for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(glm::distance(f.mesh.normals[k], n), 0, 1e-6f);
    // Without weights the targets do nothing.
    const MeshFile rest = read_mesh_file(morphed_square("rest", nullptr, {{{"mesh", 0}}}));
    EXPECT_EQ(rest.mesh.positions[2], vec3(1, 1, 0));
    EXPECT_EQ(rest.mesh.normals[2], vec3(0, 0, 1));
}

TEST(GltfGeometry, ANodesOwnWeightsMorphItsMeshApartFromTheOthers) {
    // Three nodes of one mesh: two at the mesh's weights share it; the third's own weights
    // bake a moved copy.
    const MeshFile f = read_mesh_file(
        morphed_square("node_weights", {0.0},
                       {{{"mesh", 0}},
                        {{"mesh", 0}, {"translation", {5, 0, 0}}, {"weights", {0.0}}},
                        {{"mesh", 0}, {"translation", {10, 0, 0}}, {"weights", {1.0}}}}));
    ASSERT_EQ(f.shared.size(), 1u);
    EXPECT_EQ(f.shared[0].places.size(), 2u);
    EXPECT_EQ(f.shared[0].mesh.positions[2], vec3(1, 1, 0));
    ASSERT_EQ(f.mesh.positions.size(), 4u);
    EXPECT_EQ(f.mesh.positions[2], vec3(11, 1, 1));
}

/// A triangle (0,0,0) (1,0,0) (0,1,0) placed by a node at z = -1 with EXT_mesh_gpu_instancing's
/// `attributes` (accessor fields by name), written as NAME.
fs::path gpu_instanced(const std::string& name, const std::map<std::string, json>& fields,
                       GltfWriter& w, int pos) {
    json attributes = json::object();
    for (const auto& [key, f] : fields) attributes[key] = w.accessor(f);
    return w.write(
        name, {{"meshes", one_mesh({{"POSITION", pos}})},
               {"extensionsUsed", {"EXT_mesh_gpu_instancing"}},
               {"nodes",
                {{{"mesh", 0},
                  {"translation", {0, 0, -1}},
                  {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}}}}});
}

/// A VEC3 or VEC4 float accessor of `values` in a view of its own, as accessor fields.
json floats(GltfWriter& w, const std::vector<float>& values, int n) {
    return {{"bufferView", w.view(values)},
            {"componentType", 5126},
            {"count", values.size() / static_cast<size_t>(n)},
            {"type", n == 3 ? "VEC3" : "VEC4"}};
}

TEST(GltfGeometry, GpuInstancingPlacesTheNodesMeshOnceAnElementTimesTRS) {
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const float h = std::sqrt(0.5f);  // a quarter turn about z: (0, 0, sin 45, cos 45)
    const MeshFile f = read_mesh_file(
        gpu_instanced("gpu",
                      {{"TRANSLATION", floats(w, {1, 0, 0, 2, 0, 0, 3, 0, 0}, 3)},
                       {"ROTATION", floats(w, {0, 0, 0, 1, 0, 0, h, h, 0, 0, 0, 1}, 4)},
                       {"SCALE", floats(w, {1, 1, 1, 1, 1, 1, 2, 2, 2}, 3)}},
                      w, pos));
    EXPECT_TRUE(f.warnings.empty());
    EXPECT_TRUE(f.mesh.indices.empty());
    ASSERT_EQ(f.shared.size(), 1u);
    ASSERT_EQ(f.shared[0].places.size(), 3u);
    // Vertex (1, 0, 0) of each: moved by the node (z = -1) after T R S.
    const auto at = [&](size_t k) { return vec3(f.shared[0].places[k] * vec4(1, 0, 0, 1)); };
    EXPECT_NEAR(glm::distance(at(0), vec3(2, 0, -1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(at(1), vec3(2, 1, -1)), 0.0f, 1e-6f);  // turned onto +y
    EXPECT_NEAR(glm::distance(at(2), vec3(5, 0, -1)), 0.0f, 1e-6f);  // scaled by 2
    // One element: the mesh baked in its place; a zero scale among several: baked (no
    // instance without an inverse), the others instances.
    GltfWriter one;
    const int pos1 = one.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const MeshFile single = read_mesh_file(
        gpu_instanced("gpu_one", {{"TRANSLATION", floats(one, {4, 0, 0}, 3)}}, one, pos1));
    EXPECT_TRUE(single.shared.empty());
    ASSERT_EQ(single.mesh.positions.size(), 3u);
    EXPECT_EQ(single.mesh.positions[1], vec3(5, 0, -1));
    GltfWriter flat;
    const int pos2 = flat.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const MeshFile zero = read_mesh_file(gpu_instanced(
        "gpu_zero", {{"SCALE", floats(flat, {1, 1, 1, 1, 1, 0, 1, 1, 1}, 3)}}, flat, pos2));
    ASSERT_EQ(zero.shared.size(), 1u);
    EXPECT_EQ(zero.shared[0].places.size(), 2u);
    EXPECT_EQ(zero.mesh.triangle_count(), 1u);
}

TEST(GltfGeometry, GpuInstancingsAttributesMustAgreeInCount) {
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const fs::path file = gpu_instanced(
        "gpu_counts",
        {{"TRANSLATION", floats(w, {1, 0, 0, 2, 0, 0}, 3)}, {"SCALE", floats(w, {1, 1, 1}, 3)}}, w,
        pos);
    try {
        read_mesh_file(file);
        ADD_FAILURE() << "read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("node 0 EXT_mesh_gpu_instancing: its attributes' "
                                             "counts differ"),
                  std::string::npos)
            << e.what();
    }
}

/// A SCALAR float accessor of `values` in a view of its own.
int scalars(GltfWriter& w, const std::vector<float>& values) {
    return w.accessor({{"bufferView", w.view(values)},
                       {"componentType", 5126},
                       {"count", values.size()},
                       {"type", "SCALAR"}});
}

TEST(GltfGeometry, TheFirstAnimationPosesItsNodesAtItsFirstKeys) {
    // The triangle (0,0,0) (1,0,0) (0,1,0) under a node at (9, 9, 9) turned about z: the
    // animation's first keys (its times given out of order, the earliest second) move it to
    // (1, 2, 3), scale it by 2 and, by a CUBICSPLINE rotation (in-tangent, value, out-tangent),
    // turn it a quarter about z. A second animation is not read.
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int times = scalars(w, {2, 1});
    const int one_time = scalars(w, {0});
    const int moves = w.accessor(floats(w, {7, 7, 7, 1, 2, 3}, 3));
    const int scales = w.accessor(floats(w, {2, 2, 2}, 3));
    const float h = std::sqrt(0.5f);
    const int turns = w.accessor(floats(w, {9, 9, 9, 9, 0, 0, h, h, 9, 9, 9, 9}, 4));
    const int elsewhere = w.accessor(floats(w, {50, 50, 50}, 3));
    const json animations = {
        {{"samplers",
          {{{"input", times}, {"output", moves}},
           {{"input", one_time}, {"output", scales}, {"interpolation", "STEP"}},
           {{"input", one_time}, {"output", turns}, {"interpolation", "CUBICSPLINE"}}}},
         {"channels",
          {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
           {{"sampler", 1}, {"target", {{"node", 0}, {"path", "scale"}}}},
           {{"sampler", 2}, {"target", {{"node", 0}, {"path", "rotation"}}}}}}},
        {{"samplers", {{{"input", one_time}, {"output", elsewhere}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}};
    const MeshFile f = read_mesh_file(
        w.write("animated",
                {{"meshes", one_mesh({{"POSITION", pos}})},
                 {"nodes", {{{"mesh", 0}, {"translation", {9, 9, 9}}, {"rotation", {0, 0, 1, 0}}}}},
                 {"animations", animations}}));
    ASSERT_EQ(f.mesh.positions.size(), 3u);
    EXPECT_NEAR(glm::distance(f.mesh.positions[0], vec3(1, 2, 3)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(f.mesh.positions[1], vec3(1, 4, 3)), 0.0f, 1e-5f);   // x -> y
    EXPECT_NEAR(glm::distance(f.mesh.positions[2], vec3(-1, 2, 3)), 0.0f, 1e-5f);  // y -> -x
}

TEST(GltfGeometry, AQuantisedRotationTurnsWithoutScaling) {
    // A quarter turn about z as normalised signed bytes (glTF 2.0, 3.11: 91 / 127 = 0.7165 for
    // sqrt(1/2), a quaternion 1.3 % long): the triangle turns and keeps its size.
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int time = scalars(w, {0});
    const int turn = w.accessor({{"bufferView", w.view(std::vector<int8_t>{0, 0, 91, 91})},
                                 {"componentType", 5120},
                                 {"normalized", true},
                                 {"count", 1},
                                 {"type", "VEC4"}});
    const json animations = {
        {{"samplers", {{{"input", time}, {"output", turn}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}}}}};
    const MeshFile f =
        read_mesh_file(w.write("quantised_turn", {{"meshes", one_mesh({{"POSITION", pos}})},
                                                  {"extensionsUsed", {"KHR_mesh_quantization"}},
                                                  {"nodes", {{{"mesh", 0}}}},
                                                  {"animations", animations}}));
    ASSERT_EQ(f.mesh.positions.size(), 3u);
    EXPECT_NEAR(glm::distance(f.mesh.positions[1], vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(f.mesh.positions[2], vec3(-1, 0, 0)), 0.0f, 1e-6f);
}

TEST(GltfGeometry, AnimatedMorphWeightsAreTheFirstKeys) {
    // The morphed square's mesh weight 0.5, animated to 1 (then 0).
    const fs::path plain = morphed_square("plain_weights", {0.5}, {{{"mesh", 0}}});
    json gltf;
    std::ifstream(plain) >> gltf;
    // Append the keys to the square's buffer: a new .bin holding both.
    std::ifstream in(plain.parent_path() / "plain_weights.bin", std::ios::binary);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), {});
    const auto append = [&](const std::vector<float>& v) {
        while (bytes.size() % 4 != 0) bytes.push_back(0);
        const size_t offset = bytes.size();
        bytes.resize(offset + 4 * v.size());
        std::memcpy(bytes.data() + offset, v.data(), 4 * v.size());
        gltf["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", 4 * v.size()}});
        gltf["accessors"].push_back({{"bufferView", gltf["bufferViews"].size() - 1},
                                     {"componentType", 5126},
                                     {"count", v.size()},
                                     {"type", "SCALAR"}});
        return static_cast<int>(gltf["accessors"].size()) - 1;
    };
    const int times = append({0, 1}), weights = append({1, 0});
    gltf["buffers"][0] = {{"uri", "animated_weights.bin"}, {"byteLength", bytes.size()}};
    gltf["animations"] = {
        {{"samplers", {{{"input", times}, {"output", weights}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}};
    std::ofstream(plain.parent_path() / "animated_weights.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
    std::ofstream(plain.parent_path() / "animated_weights.gltf") << gltf.dump();
    const MeshFile f = read_mesh_file(plain.parent_path() / "animated_weights.gltf");
    ASSERT_EQ(f.mesh.positions.size(), 4u);
    EXPECT_EQ(f.mesh.positions[2], vec3(1, 1, 1));
}

TEST(GltfGeometry, BadAnimationChannelsAreRefusedWithOneLine) {
    struct Case {
        const char* name;
        json channel;
        json node;
        const char* says;
    };
    const std::vector<Case> cases = {
        {"anim_node",
         {{"sampler", 0}, {"target", {{"node", 3}, {"path", "translation"}}}},
         {{"mesh", 0}},
         "animation 0, channel 0: node 3 missing"},
        {"anim_sampler",
         {{"sampler", 4}, {"target", {{"node", 0}, {"path", "translation"}}}},
         {{"mesh", 0}},
         "animation 0, channel 0: sampler 4 missing"},
        {"anim_matrix",
         {{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
         {{"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}},
         "is given by a matrix and cannot be animated"},
        {"anim_short",
         {{"sampler", 1}, {"target", {{"node", 0}, {"path", "translation"}}}},
         {{"mesh", 0}},
         "fewer outputs than keys"},
        {"anim_weights",
         {{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}},
         {{"translation", {0, 0, 0}}, {"children", {1}}},
         "weights of a node without a mesh"},
    };
    for (const Case& c : cases) {
        GltfWriter w;
        const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
        const int times = scalars(w, {1, 0});  // the earliest key is the second
        const int moves = w.accessor(floats(w, {1, 2, 3, 4, 5, 6}, 3));
        const int one = w.accessor(floats(w, {1, 2, 3}, 3));
        const json animations = {
            {{"samplers",
              {{{"input", times}, {"output", moves}}, {{"input", times}, {"output", one}}}},
             {"channels", {c.channel}}}};
        json nodes = {c.node, {{"mesh", 0}}};
        const fs::path file = w.write(c.name, {{"meshes", one_mesh({{"POSITION", pos}})},
                                               {"nodes", nodes},
                                               {"animations", animations}});
        try {
            read_mesh_file(file);
            ADD_FAILURE() << c.name << " was read";
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(c.says), std::string::npos) << c.name << ": " << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << c.name << ": " << what;
        }
    }
}

TEST(GltfGeometry, ASkinPlacesItsVerticesByItsJointsAtTheNodesPose) {
    // Three vertices: the first bound to joint 0 (at the origin), the second to joint 1 (moved
    // up by 2 and turned a quarter about z, its bind pose at (1, 0, 0)), the third half to
    // each. The mesh node's own place (x + 100) is ignored, as glTF says.
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int nor = w.vec3s({0, 0, 1, 1, 0, 0, 0, 0, 1});
    const int joints = w.accessor(
        {{"bufferView", w.view(std::vector<uint8_t>{0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0})},
         {"componentType", 5121},
         {"count", 3},
         {"type", "VEC4"}});
    const int weights = w.accessor(
        {{"bufferView", w.view(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0})},
         {"componentType", 5126},
         {"count", 3},
         {"type", "VEC4"}});
    // Joint 1's inverse bind matrix: a translation by (-1, 0, 0) (its bind pose at x = 1).
    std::vector<float> ibm(32, 0.0f);
    for (int k : {0, 5, 10, 15, 16, 21, 26, 31}) ibm[static_cast<size_t>(k)] = 1.0f;
    ibm[28] = -1.0f;
    const int inverse = w.accessor(
        {{"bufferView", w.view(ibm)}, {"componentType", 5126}, {"count", 2}, {"type", "MAT4"}});
    const float h = std::sqrt(0.5f);
    const MeshFile f = read_mesh_file(w.write(
        "skin",
        {{"meshes",
          one_mesh(
              {{"POSITION", pos}, {"NORMAL", nor}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}})},
         {"skins", {{{"joints", {1, 2}}, {"inverseBindMatrices", inverse}}}},
         {"nodes",
          {{{"mesh", 0}, {"skin", 0}, {"translation", {100, 0, 0}}},
           {{"children", {2}}},
           {{"translation", {1, 2, 0}}, {"rotation", {0, 0, h, h}}}}}},
        {0, 1}));
    ASSERT_EQ(f.mesh.positions.size(), 3u);
    EXPECT_NEAR(glm::distance(f.mesh.positions[0], vec3(0, 0, 0)), 0.0f, 1e-6f);
    // (1, 0, 0) in joint 1's bind space is its origin: placed at the joint, (1, 2, 0).
    EXPECT_NEAR(glm::distance(f.mesh.positions[1], vec3(1, 2, 0)), 0.0f, 1e-6f);
    // (0, 1, 0): half at itself, half at joint 1 turned: (-1, 1, 0) about z -> (-1, -1, 0),
    // plus (1, 2, 0) -> (0, 1, 0); the mean (0, 1, 0).
    EXPECT_NEAR(glm::distance(f.mesh.positions[2], vec3(0, 1, 0)), 0.0f, 1e-6f);
    // The second vertex's normal (1, 0, 0) turned with its joint onto +y.
    EXPECT_NEAR(glm::distance(f.mesh.normals[1], vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(f.mesh.normals[0], vec3(0, 0, 1)), 0.0f, 1e-6f);
}

TEST(GltfGeometry, NodesThatAreNotTreesAreRefusedAndWithoutASceneEachTreeIsPlacedOnce) {
    GltfWriter w;
    const int pos = w.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    // Node 2 the child of both 0 and 1: refused (it would be placed twice, and a chain of
    // such nodes doubles at each level).
    try {
        read_mesh_file(
            w.write("two_parents",
                    {{"meshes", one_mesh({{"POSITION", pos}})},
                     {"nodes", {{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}}}},
                    {0, 1}));
        ADD_FAILURE() << "read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("node 2 is the child of two nodes"), std::string::npos)
            << e.what();
    }
    // No scene: each tree from its root, so a child's mesh once, under its parent's place.
    GltfWriter v;
    const int pos2 = v.vec3s({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const fs::path file = v.write(
        "no_scene", {{"meshes", one_mesh({{"POSITION", pos2}})},
                     {"nodes", {{{"children", {1}}, {"translation", {0, 0, 5}}}, {{"mesh", 0}}}}});
    json j = json::parse(std::ifstream(file));
    j.erase("scene");
    j.erase("scenes");
    std::ofstream(file) << j.dump();
    const MeshFile f = read_mesh_file(file);
    ASSERT_EQ(f.mesh.positions.size(), 3u);  // was 6: the child also placed as a root
    EXPECT_EQ(f.mesh.positions[1], vec3(1, 0, 5));
}

/// Two squares side by side: the left without NORMAL, the right with normals tilted away
/// from its face (as an artist's smoothing may), both with uvs.
fs::path flat_and_smooth() {
    GltfWriter w;
    const int left = w.vec3s({-2, 0, 0, -1, 0, 0, -1, 1, 0, -2, 1, 0});
    const int right = w.vec3s({1, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0});
    const float s = 0.6f, c = 0.8f;
    const int nor = w.vec3s({s, 0, c, s, 0, c, s, 0, c, s, 0, c});
    const int uv = w.accessor({{"bufferView", w.view(std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0})},
                               {"componentType", 5126},
                               {"count", 4},
                               {"type", "VEC2"}});
    const int idx = w.indices({0, 1, 2, 0, 2, 3});
    json mesh = {{{"primitives",
                   {{{"attributes", {{"POSITION", left}, {"TEXCOORD_0", uv}}}, {"indices", idx}},
                    {{"attributes", {{"POSITION", right}, {"NORMAL", nor}, {"TEXCOORD_0", uv}}},
                     {"indices", idx}}}}}};
    return w.write("flat_and_smooth", {{"meshes", mesh}, {"nodes", {{{"mesh", 0}}}}});
}

TEST(GltfGeometry, APrimitiveWithoutNormalsIsFlatBesideOneWithNormals) {
    const MeshFile f = read_mesh_file(flat_and_smooth());
    ASSERT_EQ(f.mesh.normals.size(), 8u);
    for (size_t k = 0; k < 4; ++k) EXPECT_EQ(f.mesh.normals[k], vec3(0.0f)) << k;
    for (size_t k = 4; k < 8; ++k) EXPECT_NEAR(f.mesh.normals[k].x, 0.6f, 1e-6f) << k;
    // Made tangents: along +u (+x) on the flat square too, about its face's normal.
    const std::vector<vec4> t = mesh_tangents(f.mesh);
    ASSERT_EQ(t.size(), 8u);
    for (size_t k = 0; k < 4; ++k)
        EXPECT_NEAR(glm::distance(t[k], vec4(1, 0, 0, 1)), 0.0f, 1e-6f) << k;
    // As a model alone ("smooth": true) the file's normals stay and the flat ones stay flat:
    // the whole mesh's normals were computed again before (the right square then faced +z).
    const Scene scene = load_scene(flat_and_smooth());
    ASSERT_EQ(scene.objects.size(), 1u);
    const Mesh& m = std::get<Mesh>(scene.objects[0].shape);
    ASSERT_EQ(m.normals.size(), 8u);
    for (size_t k = 0; k < 4; ++k) EXPECT_EQ(m.normals[k], vec3(0.0f)) << k;
    for (size_t k = 4; k < 8; ++k) EXPECT_NEAR(m.normals[k].x, 0.6f, 1e-6f) << k;
}

}  // namespace
}  // namespace svetlo
