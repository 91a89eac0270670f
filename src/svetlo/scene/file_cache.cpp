#include "svetlo/scene/file_cache.h"

namespace svetlo {
namespace fs = std::filesystem;

std::string file_stamp(const fs::path& path) {
    std::error_code size_error, time_error;
    const auto size = fs::file_size(path, size_error);
    const auto time = fs::last_write_time(path, time_error);
    if (size_error || time_error) return "";
    return std::to_string(size) + " " +
           std::to_string(static_cast<long long>(time.time_since_epoch().count()));
}

std::shared_ptr<const MeshFile> FileCache::read(const fs::path& path, const FileScope& files) {
    const std::string stamp = file_stamp(path);
    std::lock_guard<std::mutex> lock(mutex_);
    MeshEntry& entry = meshes_[path.lexically_normal().string()];
    if (!entry.file || entry.stamp != stamp || stamp.empty()) {
        entry.file = std::make_shared<const MeshFile>(read_mesh_file(path, files));
        entry.stamp = stamp;
    }
    return entry.file;
}

TextureImage FileCache::read_texture(const fs::path& path, TexelMeaning meaning, size_t max_bytes,
                                     const std::string& where, NegativeTexels negative) {
    const std::string stamp = file_stamp(path);
    std::lock_guard<std::mutex> lock(mutex_);
    ImageEntry& entry = images_[{path.lexically_normal().string(), meaning, negative}];
    // Read again where the file changed, or where this scene has less texture memory left
    // than the texture takes (read_texture then refuses it, as it would have).
    if (entry.texture.bytes() == 0 || entry.stamp != stamp || stamp.empty() ||
        entry.texture.bytes() > max_bytes) {
        entry.texture = TextureImage();  // the old texels freed first; none kept if this throws
        entry.texture = svetlo::read_texture(path, meaning, max_bytes, where, negative);
        entry.stamp = stamp;
    }
    return entry.texture;
}

}  // namespace svetlo
