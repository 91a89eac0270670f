// Files read once: the mesh files and images a scene names, shared by the scenes of one
// command (svetlo compare, svetlo serve's requests, a scene that names a file twice). A file
// whose size or time has changed since is read again.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

#include "svetlo/core/image_io.h"
#include "svetlo/scene/mesh_file.h"

namespace svetlo {

/// A file's size and modification time, as text ("" where it cannot be read): what tells
/// that a file has changed since it was read.
std::string file_stamp(const std::filesystem::path& path);

class FileCache {
public:
    /// read_mesh_file(path), or what it returned before for the file as it is now. Safe to
    /// call from several threads.
    std::shared_ptr<const MeshFile> read(const std::filesystem::path& path,
                                         const FileScope& files = {});

    /// read_texture(path, meaning, max_bytes, where, negative), or what it returned before
    /// for the file as it is now, read with the same meaning (a copy shares its texels:
    /// core/texture_image.h). Safe to call from several threads.
    TextureImage read_texture(const std::filesystem::path& path, TexelMeaning meaning,
                              size_t max_bytes, const std::string& where,
                              NegativeTexels negative = NegativeTexels::Refuse);

private:
    struct MeshEntry {
        std::string stamp;  // size and time
        std::shared_ptr<const MeshFile> file;
    };
    struct ImageEntry {
        std::string stamp;
        TextureImage texture;
    };
    std::mutex mutex_;
    std::map<std::string, MeshEntry> meshes_;  // by path: one entry per file
    std::map<std::tuple<std::string, TexelMeaning, NegativeTexels>, ImageEntry> images_;
};

}  // namespace svetlo
