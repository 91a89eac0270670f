// glTF 2.0 (.gltf and .glb) through tinygltf: the files a model names, read inside its folder
// (image files by the threads that decode them), the extensions checked; its compressed
// geometry (gltf_compression.h), its materials (gltf_materials.h) and what its nodes place
// (gltf_flatten.h).
#include <tiny_gltf.h>

#include <algorithm>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "svetlo/core/image_io.h"
#include "svetlo/core/image_signature.h"
#include "svetlo/core/input_file.h"
#include "svetlo/scene/gltf_compression.h"
#include "svetlo/scene/gltf_flatten.h"
#include "svetlo/scene/gltf_materials.h"
#include "svetlo/scene/gltf_nodes.h"
#include "svetlo/scene/mesh_file.h"

namespace svetlo {

namespace {

/// What tinygltf's file callbacks know: the folder the files must lie in, the model file
/// itself as tinygltf can load it (tinygltf_loadable; empty: the file as it is), and the image
/// files left for the threads that decode them (GltfImageFiles).
struct GltfFiles {
    const FileScope* scope;
    std::string model;
    std::vector<unsigned char> loadable;
    bool defer_images = true;
    std::vector<std::string> deferred;  // the files read_checked_file handed over as markers
    GltfImageFiles image_files;         // image index -> its file, as keep_encoded found them
};

/// What tinygltf is handed in place of an image file left for later: this, then the index
/// of the file in GltfFiles::deferred.
constexpr std::string_view kDeferredImage = "svetlo: an image file read later, #";

/// Whether the file begins as a PNG, JPEG or WebP image does (its first bytes).
bool starts_as_image(const std::string& path) {
    unsigned char head[kImageSignatureBytes] = {};
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(head), sizeof head);
    const auto n = static_cast<size_t>(in.gcount());
    return is_png(head, n) || is_jpeg(head, n) || is_webp(head, n);
}

/// tinygltf's file reading with every file checked first (buffers and images a glTF names),
/// as svetlo checks every input file, and inside the FileScope of the GltfFiles that
/// `user_data` points to. An image file is not read here: tinygltf gets a marker in its place
/// (kDeferredImage), and the file is read by the thread that decodes it (a model's textures
/// are most of its bytes; read here, each would be read, then copied, on one thread).
bool read_checked_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                       void* user_data) {
    auto* files = static_cast<GltfFiles*>(user_data);
    if (path == files->model && !files->loadable.empty()) {
        *out = files->loadable;
        return true;
    }
    if (names_network(path)) {
        if (err) *err += "'" + path + "' " + kNetwork + "\n";
        return false;
    }
    try {
        files->scope->resolve({}, path);
    } catch (const std::runtime_error& e) {
        if (err) *err += std::string(e.what()) + "\n";
        return false;
    }
    std::string problem = input_file_problem(path);
    if (!problem.empty()) {
        if (err) *err += "'" + path + "' " + problem + "\n";
        return false;
    }
    if (files->defer_images && path != files->model && starts_as_image(path)) {
        const std::string marker =
            std::string(kDeferredImage) + std::to_string(files->deferred.size());
        files->deferred.push_back(path);
        out->assign(marker.begin(), marker.end());
        return true;
    }
    return tinygltf::ReadWholeFile(out, err, path, nullptr);
}

/// Whether `bytes` are one of the markers read_checked_file handed out; its index into
/// `files.deferred`. (An image written into the file that reads as a marker can only name one
/// of the model's own image files.)
std::optional<size_t> deferred_index(const GltfFiles& files, const unsigned char* bytes,
                                     size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(bytes), size);
    if (text.substr(0, kDeferredImage.size()) != kDeferredImage) return std::nullopt;
    const std::string_view digits = text.substr(kDeferredImage.size());
    if (digits.empty() || digits.size() > 9) return std::nullopt;
    size_t k = 0;
    for (char c : digits) {
        if (c < '0' || c > '9') return std::nullopt;
        k = 10 * k + static_cast<size_t>(c - '0');
    }
    if (k >= files.deferred.size()) return std::nullopt;
    return k;
}

/// tinygltf's image callback: the encoded bytes kept as they are, for GltfTextures to decode
/// the images a material uses, once per colour space; or, for a file left for later, its
/// name under the image's index.
bool keep_encoded(tinygltf::Image* image, int index, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user_data) {
    auto* files = static_cast<GltfFiles*>(user_data);
    image->width = image->height = image->component = image->bits = 0;
    if (const auto k = deferred_index(*files, bytes, static_cast<size_t>(size))) {
        files->image_files[index] = files->deferred[*k];
        image->image.clear();
        return true;
    }
    image->image.assign(bytes, bytes + size);
    return true;
}

/// The extensions svetlo reads (docs/scene-format.md, "Mesh files"), those of the libraries
/// a build may lack (libwebp) where it has them.
bool reads_extension(const std::string& name) {
    constexpr std::string_view always[] = {
        "KHR_lights_punctual",    "KHR_materials_emissive_strength",
        "KHR_materials_ior",      "KHR_materials_transmission",
        "KHR_materials_volume",   "KHR_materials_clearcoat",
        "KHR_mesh_quantization",  "KHR_texture_transform",
        "KHR_materials_specular", "KHR_materials_unlit",
        "EXT_mesh_gpu_instancing"};
    if (name == "EXT_texture_webp") return reads_webp();
    if (decodes_compression(name)) return true;
    return std::find(std::begin(always), std::end(always), name) != std::end(always);
}

/// A required extension svetlo does not read refuses the file; an optional one is a warning.
void check_extensions(const tinygltf::Model& model, MeshFile& file) {
    const auto read = [](const std::string& name) { return reads_extension(name); };
    for (const std::string& name : model.extensionsRequired)
        if (!read(name))
            throw std::runtime_error("extensionsRequired names '" + name +
                                     "', which svetlo does not read");
    for (const std::string& name : model.extensionsUsed) {
        file.extensions.push_back(read(name) ? name : name + " (ignored)");
        if (!read(name)) file.warnings.push_back("extension '" + name + "' is not read: ignored");
    }
}

/// tinygltf's question whether a file exists, answered yes for a network URI so that
/// read_checked_file refuses it by name (tinygltf would say "File not found").
bool exists_or_network(const std::string& path, void* user_data) {
    return names_network(path) || tinygltf::FileExists(path, user_data);
}

}  // namespace

MeshFile read_gltf(const std::filesystem::path& path, const FileScope& files) {
    const bool binary = path.extension() == ".glb" || path.extension() == ".GLB";
    GltfFiles reading{&files, path.string(), tinygltf_loadable(path, binary), true, {}, {}};
    tinygltf::Model model;
    std::string err, warn;
    const auto load = [&] {
        tinygltf::TinyGLTF loader;
        loader.SetFsCallbacks({&exists_or_network, &tinygltf::ExpandFilePath, &read_checked_file,
                               &tinygltf::WriteWholeFile, &reading});
        loader.SetImageLoader(&keep_encoded, &reading);
        return binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                      : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
    };
    bool ok = load();
    // A file that begins as an image and that the glTF names as a buffer (legal, if rare)
    // got a marker in its place: the whole file is read again, every file read by tinygltf.
    const auto marker = [&reading](const tinygltf::Buffer& b) {
        return deferred_index(reading, b.data.data(), b.data.size()).has_value();
    };
    if (!reading.deferred.empty() &&
        (!ok || std::any_of(model.buffers.begin(), model.buffers.end(), marker))) {
        reading.defer_images = false;
        reading.deferred.clear();
        reading.image_files.clear();
        model = tinygltf::Model();
        err.clear();
        warn.clear();
        ok = load();
    }
    if (!ok) {
        // tinygltf may say several things, a line each: one line, joined.
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        for (size_t k = err.find('\n'); k != std::string::npos; k = err.find('\n', k))
            err.replace(k, 1, "; ");
        throw std::runtime_error(err.empty() ? "cannot parse glTF" : err);
    }
    MeshFile file;
    check_extensions(model, file);
    decompress_geometry(model);
    read_gltf_materials(model, reading.image_files, file);
    pose_first_keys(model);
    place_gltf_nodes(model, file);
    return file;
}

}  // namespace svetlo
