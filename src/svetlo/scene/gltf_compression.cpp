#include "svetlo/scene/gltf_compression.h"

#include <tiny_gltf.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#ifdef SVETLO_HAS_DRACO
#include <draco/compression/decode.h>
#endif
#ifdef SVETLO_HAS_MESHOPT
#include <meshoptimizer.h>
#endif

namespace svetlo {

namespace {

#if defined(SVETLO_HAS_DRACO) || defined(SVETLO_HAS_MESHOPT)
/// The bytes [offset, offset + length) of buffer view `index`, checked against its buffer.
const unsigned char* view_bytes(const tinygltf::Model& model, int index, size_t& length) {
    if (index < 0 || static_cast<size_t>(index) >= model.bufferViews.size())
        throw std::runtime_error("buffer view " + std::to_string(index) + " missing");
    const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(index)];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
        throw std::runtime_error("buffer view " + std::to_string(index) + " without a buffer");
    const tinygltf::Buffer& buffer = model.buffers[static_cast<size_t>(view.buffer)];
    if (view.byteOffset > buffer.data.size() ||
        view.byteLength > buffer.data.size() - view.byteOffset)
        throw std::runtime_error("buffer view " + std::to_string(index) + " runs past its buffer");
    length = view.byteLength;
    return buffer.data.data() + view.byteOffset;
}

/// A new buffer holding `bytes`, and a buffer view of all of it (with `stride`, 0 for none):
/// the new view's index.
int add_view(tinygltf::Model& model, std::vector<unsigned char> bytes, size_t stride) {
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes);
    tinygltf::BufferView view;
    view.buffer = static_cast<int>(model.buffers.size());
    view.byteOffset = 0;
    view.byteLength = buffer.data.size();
    view.byteStride = stride;
    model.buffers.push_back(std::move(buffer));
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size()) - 1;
}
#endif

#ifdef SVETLO_HAS_DRACO
/// Accessor `index` pointed at `bytes`: `count` elements of its type, as floats.
void point_accessor(tinygltf::Model& model, int index, std::vector<unsigned char> bytes,
                    size_t count, int component_type) {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
        throw std::runtime_error("accessor " + std::to_string(index) + " missing");
    tinygltf::Accessor& a = model.accessors[static_cast<size_t>(index)];
    a.bufferView = add_view(model, std::move(bytes), 0);
    a.byteOffset = 0;
    a.count = count;
    a.componentType = component_type;
    a.normalized = false;
    a.sparse = {};
}

/// One primitive's Draco mesh (KHR_draco_mesh_compression, 1.0): its faces as the indices,
/// each attribute the extension names (by its Draco unique id) as floats.
void decode_draco(tinygltf::Model& model, tinygltf::Primitive& prim, const tinygltf::Value& ext) {
    if (!ext.Has("bufferView") || !ext.Has("attributes"))
        throw std::runtime_error("KHR_draco_mesh_compression without bufferView or attributes");
    size_t length = 0;
    const unsigned char* bytes = view_bytes(model, ext.Get("bufferView").GetNumberAsInt(), length);
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes), length);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) throw std::runtime_error("Draco: " + decoded.status().error_msg_string());
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    const size_t points = mesh->num_points();
    // The indices, 32-bit (a Draco point is a glTF vertex).
    std::vector<unsigned char> indices(3 * mesh->num_faces() * sizeof(uint32_t));
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = mesh->face(f)[k].value();
            std::memcpy(&indices[(3 * f.value() + k) * sizeof(uint32_t)], &i, sizeof i);
        }
    if (prim.indices < 0) {  // left out for tinygltf (tinygltf_loadable), or forgotten
        tinygltf::Accessor a;
        a.type = TINYGLTF_TYPE_SCALAR;
        model.accessors.push_back(a);
        prim.indices = static_cast<int>(model.accessors.size()) - 1;
    }
    point_accessor(model, prim.indices, std::move(indices), 3 * mesh->num_faces(),
                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    const tinygltf::Value& attributes = ext.Get("attributes");
    for (const std::string& name : attributes.Keys()) {
        const auto target = prim.attributes.find(name);
        if (target == prim.attributes.end()) continue;  // not among the primitive's: unused
        const draco::PointAttribute* attribute = mesh->GetAttributeByUniqueId(
            static_cast<uint32_t>(attributes.Get(name).GetNumberAsInt()));
        if (!attribute) throw std::runtime_error("Draco: no attribute for " + name);
        const int n = attribute->num_components();
        if (n < 1 || n > 4)
            throw std::runtime_error("Draco: " + name + " has " + std::to_string(n) +
                                     " components");
        std::vector<unsigned char> values(points * static_cast<size_t>(n) * sizeof(float));
        float v[4];
        for (draco::PointIndex p(0); p < points; ++p) {
            if (!attribute->ConvertValue<float>(attribute->mapped_index(p), static_cast<int8_t>(n),
                                                v))
                throw std::runtime_error("Draco: " + name + " does not convert to floats");
            std::memcpy(&values[p.value() * static_cast<size_t>(n) * sizeof(float)], v,
                        static_cast<size_t>(n) * sizeof(float));
        }
        point_accessor(model, target->second, std::move(values), points,
                       TINYGLTF_COMPONENT_TYPE_FLOAT);
    }
}
#endif

#ifdef SVETLO_HAS_MESHOPT
/// A buffer view's EXT_meshopt_compression data decoded into a new buffer, the view pointed
/// at it (the extension's byteStride, count and mode; its filter applied).
void decode_meshopt(tinygltf::Model& model, tinygltf::BufferView& view,
                    const tinygltf::Value& ext) {
    auto number = [&](const char* key, int fallback) {
        return ext.Has(key) ? ext.Get(key).GetNumberAsInt() : fallback;
    };
    auto text = [&](const char* key, const char* fallback) {
        return ext.Has(key) ? ext.Get(key).Get<std::string>() : std::string(fallback);
    };
    const int buffer_index = number("buffer", -1), offset = number("byteOffset", 0),
              length = number("byteLength", -1), stride = number("byteStride", 0),
              count = number("count", -1);
    if (buffer_index < 0 || static_cast<size_t>(buffer_index) >= model.buffers.size() ||
        offset < 0 || length < 0 || stride <= 0 || stride > 256 || count < 0)
        throw std::runtime_error(
            "EXT_meshopt_compression: buffer, byteLength, byteStride or count missing or wrong");
    const std::vector<unsigned char>& source =
        model.buffers[static_cast<size_t>(buffer_index)].data;
    if (static_cast<size_t>(offset) + static_cast<size_t>(length) > source.size())
        throw std::runtime_error("EXT_meshopt_compression: the data runs past its buffer");
    const unsigned char* in = source.data() + offset;
    const size_t n = static_cast<size_t>(count), size = static_cast<size_t>(stride);
    // A compressed stream holds at least a byte for every 256 elements' bytes (its
    // header and tail): a count beyond that is a forged header, refused before allocating.
    if (n * size > 256 * (static_cast<size_t>(length) + 1))
        throw std::runtime_error("EXT_meshopt_compression: count is more than the data holds");
    std::vector<unsigned char> out(n * size);
    const std::string mode = text("mode", "ATTRIBUTES"), filter = text("filter", "NONE");
    int failed = 0;
    if (mode == "ATTRIBUTES") {
        if (size % 4 != 0)
            throw std::runtime_error("EXT_meshopt_compression: byteStride not a multiple of 4");
        failed = meshopt_decodeVertexBuffer(out.data(), n, size, in, static_cast<size_t>(length));
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (size != 2 && size != 4)
            throw std::runtime_error("EXT_meshopt_compression: indices of " + std::to_string(size) +
                                     " bytes");
        failed =
            mode == "TRIANGLES"
                ? meshopt_decodeIndexBuffer(out.data(), n, size, in, static_cast<size_t>(length))
                : meshopt_decodeIndexSequence(out.data(), n, size, in, static_cast<size_t>(length));
    } else {
        throw std::runtime_error("EXT_meshopt_compression: unknown mode '" + mode + "'");
    }
    if (failed != 0) throw std::runtime_error("EXT_meshopt_compression: the data does not decode");
    if (filter == "OCTAHEDRAL")
        meshopt_decodeFilterOct(out.data(), n, size);
    else if (filter == "QUATERNION")
        meshopt_decodeFilterQuat(out.data(), n, size);
    else if (filter == "EXPONENTIAL")
        meshopt_decodeFilterExp(out.data(), n, size);
    else if (filter != "NONE")
        throw std::runtime_error("EXT_meshopt_compression: unknown filter '" + filter + "'");
    const int made = add_view(model, std::move(out), 0);
    const tinygltf::BufferView& decoded = model.bufferViews[static_cast<size_t>(made)];
    view.buffer = decoded.buffer;
    view.byteOffset = 0;
    view.byteLength = decoded.byteLength;
    if (mode == "ATTRIBUTES") view.byteStride = size;
}
#endif

}  // namespace

std::vector<unsigned char> tinygltf_loadable(const std::filesystem::path& path, bool binary) {
    const bool meshopt = decodes_compression("EXT_meshopt_compression"),
               draco = decodes_compression("KHR_draco_mesh_compression");
    if (!meshopt && !draco) return {};
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (!(meshopt && text.find("EXT_meshopt_compression") != std::string_view::npos) &&
        !(draco && text.find("KHR_draco_mesh_compression") != std::string_view::npos))
        return {};
    // GLB (glTF 2.0, 4.4): a 12-byte header, then the JSON chunk and the binary one, each
    // a length and a type before its bytes.
    size_t json_at = 0, json_length = bytes.size();
    auto u32 = [&](size_t at) {
        uint32_t v = 0;
        if (at + 4 <= bytes.size()) std::memcpy(&v, &bytes[at], 4);
        return static_cast<size_t>(v);
    };
    if (binary) {
        json_at = 20;
        json_length = u32(12);
        if (bytes.size() < 20 || json_length > bytes.size() - 20) return {};  // tinygltf says why
    }
    nlohmann::json gltf = nlohmann::json::parse(
        bytes.begin() + static_cast<std::ptrdiff_t>(json_at),
        bytes.begin() + static_cast<std::ptrdiff_t>(json_at + json_length), nullptr, false);
    if (gltf.is_discarded() || !gltf.is_object()) return {};  // tinygltf says why
    bool patched = false;
    auto extension = [](const nlohmann::json& o, const char* name) -> const nlohmann::json* {
        if (auto e = o.find("extensions"); e != o.end() && e->is_object())
            if (auto x = e->find(name); x != e->end() && x->is_object()) return &*x;
        return nullptr;
    };
    if (auto meshes = gltf.find("meshes"); draco && meshes != gltf.end() && meshes->is_array())
        for (nlohmann::json& mesh : *meshes) {
            if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
                continue;
            for (nlohmann::json& prim : mesh["primitives"])
                if (prim.is_object() && extension(prim, "KHR_draco_mesh_compression") &&
                    prim.erase("indices") > 0)
                    patched = true;
        }
    nlohmann::json none = nlohmann::json::array();
    auto buffers = gltf.find("buffers");
    for (nlohmann::json& buffer :
         meshopt&& buffers != gltf.end() && buffers->is_array() ? *buffers : none) {
        if (!buffer.is_object() || buffer.contains("uri")) continue;
        const nlohmann::json* ext = extension(buffer, "EXT_meshopt_compression");
        if (!ext || !ext->value("fallback", false)) continue;
        buffer["uri"] = "data:application/octet-stream;base64,AAAA";  // 3 zero bytes
        buffer["byteLength"] = 3;
        patched = true;
    }
    if (!patched) return {};
    std::string json_text = gltf.dump();
    if (!binary) return {json_text.begin(), json_text.end()};
    while (json_text.size() % 4 != 0) json_text += ' ';
    std::vector<unsigned char> out(bytes.begin(), bytes.begin() + 12);
    auto put = [&](size_t v) {
        const auto x = static_cast<uint32_t>(v);
        out.insert(out.end(), reinterpret_cast<const unsigned char*>(&x),
                   reinterpret_cast<const unsigned char*>(&x) + 4);
    };
    put(json_text.size());
    out.insert(out.end(), bytes.begin() + 16, bytes.begin() + 20);  // "JSON"
    out.insert(out.end(), json_text.begin(), json_text.end());
    out.insert(out.end(), bytes.begin() + static_cast<std::ptrdiff_t>(20 + json_length),
               bytes.end());
    const auto total = static_cast<uint32_t>(out.size());
    std::memcpy(&out[8], &total, 4);
    return out;
}

bool decodes_compression(const std::string& name) {
#ifdef SVETLO_HAS_DRACO
    if (name == "KHR_draco_mesh_compression") return true;
#endif
#ifdef SVETLO_HAS_MESHOPT
    if (name == "EXT_meshopt_compression") return true;
#endif
    (void)name;
    return false;
}

void decompress_geometry(tinygltf::Model& model) {
#ifdef SVETLO_HAS_MESHOPT
    // Views first (a Draco stream never lies in a meshopt view); by index, as the list grows.
    for (size_t k = 0, end = model.bufferViews.size(); k < end; ++k) {
        const auto ext = model.bufferViews[k].extensions.find("EXT_meshopt_compression");
        if (ext == model.bufferViews[k].extensions.end()) continue;
        const tinygltf::Value value = ext->second;
        try {
            tinygltf::BufferView view = model.bufferViews[k];
            decode_meshopt(model, view, value);
            view.extensions.erase("EXT_meshopt_compression");
            model.bufferViews[k] = view;
        } catch (const std::runtime_error& e) {
            throw std::runtime_error("buffer view " + std::to_string(k) + ": " + e.what());
        }
    }
#endif
#ifdef SVETLO_HAS_DRACO
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            tinygltf::Primitive prim = model.meshes[m].primitives[p];
            const auto ext = prim.extensions.find("KHR_draco_mesh_compression");
            if (ext == prim.extensions.end()) continue;
            const tinygltf::Value value = ext->second;
            try {
                decode_draco(model, prim, value);
            } catch (const std::runtime_error& e) {
                throw std::runtime_error("mesh " + std::to_string(m) + " primitive " +
                                         std::to_string(p) + ": " + e.what());
            }
            prim.extensions.erase("KHR_draco_mesh_compression");
            model.meshes[m].primitives[p] = prim;
        }
    }
#endif
    (void)model;
}

}  // namespace svetlo
