// glTF's compressed geometry (docs/scene-format.md, "Mesh files"): a grid written plain, with
// KHR_draco_mesh_compression (encoded here by libdraco) and with EXT_meshopt_compression
// (encoded here by meshoptimizer) reads as the same triangles; a stream that does not decode
// names its mesh or buffer view.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "svetlo/scene/mesh_file.h"

#ifdef SVETLO_HAS_DRACO
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#endif
#ifdef SVETLO_HAS_MESHOPT
#include <meshoptimizer.h>
#endif

namespace svetlo {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A 5 x 5 grid of vertices on z = x y / 4 (32 triangles), with uvs.
struct Grid {
    std::vector<float> positions, uvs;  // 3 and 2 a vertex
    std::vector<uint32_t> indices;
    Grid() {
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                positions.insert(positions.end(), {float(i), float(j), 0.25f * float(i * j)});
                uvs.insert(uvs.end(), {0.25f * float(i), 0.25f * float(j)});
            }
        for (uint32_t j = 0; j < 4; ++j)
            for (uint32_t i = 0; i < 4; ++i) {
                const uint32_t a = 5 * j + i;
                indices.insert(indices.end(), {a, a + 1, a + 6, a, a + 6, a + 5});
            }
    }
    size_t vertices() const { return positions.size() / 3; }
};

fs::path folder() {
    const fs::path dir = fs::temp_directory_path() / "svetlo_gltf_compression";
    fs::create_directories(dir);
    return dir;
}

/// A glTF of one primitive whose accessors are POSITION 0, TEXCOORD_0 1 and indices 2, with
/// `views` and `buffers` given, and `extra` merged in.
fs::path write_gltf(const std::string& name, const Grid& g, const json& views, const json& buffers,
                    const json& accessor_views, const json& extra = json::object()) {
    json accessors = {{{"componentType", 5126},
                       {"count", g.vertices()},
                       {"type", "VEC3"},
                       {"min", {0, 0, 0}},
                       {"max", {4, 4, 4}}},
                      {{"componentType", 5126}, {"count", g.vertices()}, {"type", "VEC2"}},
                      {{"componentType", 5125}, {"count", g.indices.size()}, {"type", "SCALAR"}}};
    for (size_t k = 0; k < 3; ++k)
        if (!accessor_views[k].is_null()) accessors[k]["bufferView"] = accessor_views[k];
    json gltf = {{"asset", {{"version", "2.0"}}},
                 {"scene", 0},
                 {"scenes", {{{"nodes", {0}}}}},
                 {"nodes", {{{"mesh", 0}}}},
                 {"meshes",
                  {{{"primitives",
                     {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}}}}}}},
                 {"accessors", accessors},
                 {"bufferViews", views},
                 {"buffers", buffers}};
    gltf.merge_patch(extra);
    std::ofstream(folder() / (name + ".gltf")) << gltf.dump();
    return folder() / (name + ".gltf");
}

void write_bin(const std::string& name, const std::vector<unsigned char>& bytes) {
    std::ofstream(folder() / name, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
}

template <class T>
void append(std::vector<unsigned char>& out, const std::vector<T>& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    out.insert(out.end(), p, p + v.size() * sizeof(T));
}

/// The plain file: three views of one buffer.
fs::path write_plain(const Grid& g) {
    std::vector<unsigned char> bin;
    append(bin, g.positions);
    append(bin, g.uvs);
    append(bin, g.indices);
    write_bin("plain.bin", bin);
    const size_t p = g.positions.size() * 4, u = g.uvs.size() * 4, i = g.indices.size() * 4;
    return write_gltf("plain", g,
                      {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", p}},
                       {{"buffer", 0}, {"byteOffset", p}, {"byteLength", u}},
                       {{"buffer", 0}, {"byteOffset", p + u}, {"byteLength", i}}},
                      {{{"uri", "plain.bin"}, {"byteLength", bin.size()}}}, {0, 1, 2});
}

/// Each triangle as its three corners (position, then uv), sorted, the list sorted: the
/// triangles whatever their order and their first corner.
std::vector<std::array<float, 15>> triangles(const Mesh& m, float grid) {
    std::vector<std::array<float, 15>> out;
    for (size_t t = 0; t < m.triangle_count(); ++t) {
        std::array<std::array<float, 5>, 3> corners;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = m.indices[3 * t + k];
            const vec3 p = m.positions[v];
            const vec2 uv = m.uvs[v];
            corners[k] = {p.x, p.y, p.z, uv.x, uv.y};
            for (float& x : corners[k]) x = std::round(x / grid) * grid;  // Draco quantizes
        }
        std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()),
                    corners.end());  // the first corner the least, the winding kept
        std::array<float, 15> flat;
        for (int k = 0; k < 3; ++k) std::copy(corners[k].begin(), corners[k].end(), &flat[5 * k]);
        out.push_back(flat);
    }
    std::sort(out.begin(), out.end());
    return out;
}

#ifdef SVETLO_HAS_DRACO
TEST(GltfCompression, ADracoMeshReadsAsThePlainOne) {
    const Grid g;
    const size_t faces = g.indices.size() / 3;
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(static_cast<int>(faces));
    const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const int tex = builder.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
    for (size_t f = 0; f < faces; ++f) {
        const uint32_t* v = &g.indices[3 * f];
        builder.SetAttributeValuesForFace(pos, draco::FaceIndex(static_cast<uint32_t>(f)),
                                          &g.positions[3 * v[0]], &g.positions[3 * v[1]],
                                          &g.positions[3 * v[2]]);
        builder.SetAttributeValuesForFace(tex, draco::FaceIndex(static_cast<uint32_t>(f)),
                                          &g.uvs[2 * v[0]], &g.uvs[2 * v[1]], &g.uvs[2 * v[2]]);
    }
    const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    ASSERT_NE(mesh, nullptr);
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 16);
    draco::EncoderBuffer encoded;
    ASSERT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &encoded).ok());
    std::vector<unsigned char> bin(encoded.data(), encoded.data() + encoded.size());
    write_bin("draco.bin", bin);
    const json draco = {{"bufferView", 0},
                        {"attributes",
                         {{"POSITION", mesh->attribute(pos)->unique_id()},
                          {"TEXCOORD_0", mesh->attribute(tex)->unique_id()}}}};
    const json extra = {{"extensionsUsed", {"KHR_draco_mesh_compression"}},
                        {"extensionsRequired", {"KHR_draco_mesh_compression"}},
                        {"meshes",
                         {{{"primitives",
                            {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}},
                              {"indices", 2},
                              {"extensions", {{"KHR_draco_mesh_compression", draco}}}}}}}}}};
    const fs::path file = write_gltf(
        "draco", g, {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bin.size()}}},
        {{{"uri", "draco.bin"}, {"byteLength", bin.size()}}}, {nullptr, nullptr, nullptr}, extra);
    const MeshFile compressed = read_mesh_file(file);
    const MeshFile plain = read_mesh_file(write_plain(g));
    EXPECT_TRUE(compressed.warnings.empty());
    ASSERT_EQ(compressed.mesh.triangle_count(), plain.mesh.triangle_count());
    // 16 bits over a range of 4: steps of 6e-5; compared on a grid of 1e-3.
    EXPECT_EQ(triangles(compressed.mesh, 1e-3f), triangles(plain.mesh, 1e-3f));

    // A stream cut short names the mesh and primitive.
    write_bin("draco.bin", std::vector<unsigned char>(bin.begin(), bin.begin() + 10));
    try {
        write_gltf("draco", g, {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 10}}},
                   {{{"uri", "draco.bin"}, {"byteLength", 10}}}, {nullptr, nullptr, nullptr},
                   extra);
        read_mesh_file(file);
        ADD_FAILURE() << "a cut Draco stream was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("mesh 0 primitive 0: Draco"), std::string::npos)
            << e.what();
    }
}
#endif

#ifdef SVETLO_HAS_MESHOPT
TEST(GltfCompression, AMeshoptFileReadsAsThePlainOne) {
    const Grid g;
    // Each view compressed alone; the fallback buffer (glTF's uncompressed size) has no data.
    std::vector<unsigned char> bin;
    json views = json::array();
    auto compress = [&](std::vector<unsigned char> out, size_t stride, size_t count,
                        const char* mode, size_t fallback_offset) {
        views.push_back({{"buffer", 1},
                         {"byteOffset", fallback_offset},
                         {"byteLength", stride * count},
                         {"extensions",
                          {{"EXT_meshopt_compression",
                            {{"buffer", 0},
                             {"byteOffset", bin.size()},
                             {"byteLength", out.size()},
                             {"byteStride", stride},
                             {"count", count},
                             {"mode", mode}}}}}});
        bin.insert(bin.end(), out.begin(), out.end());
        while (bin.size() % 4) bin.push_back(0);
    };
    auto vertices = [&](const std::vector<float>& v, size_t stride) {
        const size_t count = v.size() * 4 / stride;
        std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(count, stride));
        out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), v.data(), count, stride));
        return out;
    };
    const size_t n = g.vertices();
    compress(vertices(g.positions, 12), 12, n, "ATTRIBUTES", 0);
    compress(vertices(g.uvs, 8), 8, n, "ATTRIBUTES", 12 * n);
    std::vector<unsigned char> indices(meshopt_encodeIndexBufferBound(g.indices.size(), n));
    indices.resize(meshopt_encodeIndexBuffer(indices.data(), indices.size(), g.indices.data(),
                                             g.indices.size()));
    compress(indices, 4, g.indices.size(), "TRIANGLES", 20 * n);
    write_bin("meshopt.bin", bin);
    const size_t fallback = 20 * n + 4 * g.indices.size();
    const fs::path file =
        write_gltf("meshopt", g, views,
                   {{{"uri", "meshopt.bin"}, {"byteLength", bin.size()}},
                    {{"byteLength", fallback},
                     {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}},
                   {0, 1, 2},
                   {{"extensionsUsed", {"EXT_meshopt_compression"}},
                    {"extensionsRequired", {"EXT_meshopt_compression"}}});
    const MeshFile compressed = read_mesh_file(file);
    const MeshFile plain = read_mesh_file(write_plain(g));
    EXPECT_TRUE(compressed.warnings.empty());
    // Lossless: the vertices in their order, each triangle's corners rotated at most (the
    // index codec keeps the winding, not the first corner).
    EXPECT_EQ(compressed.mesh.positions, plain.mesh.positions);
    EXPECT_EQ(compressed.mesh.uvs, plain.mesh.uvs);
    EXPECT_EQ(triangles(compressed.mesh, 1e-6f), triangles(plain.mesh, 1e-6f));

    // Data that does not decode names the buffer view.
    std::fill(bin.begin(), bin.end(), 0xff);
    write_bin("meshopt.bin", bin);
    try {
        read_mesh_file(file);
        ADD_FAILURE() << "meshopt data that does not decode was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("buffer view 0: EXT_meshopt_compression"),
                  std::string::npos)
            << e.what();
    }
}
#endif

}  // namespace
}  // namespace svetlo
