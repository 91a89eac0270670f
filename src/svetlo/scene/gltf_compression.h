// glTF's compressed geometry (docs/scene-format.md, "Mesh files"), decoded in place before
// the reader walks the file: KHR_draco_mesh_compression (Google's Draco, Debian's
// libdraco-dev) and EXT_meshopt_compression (meshoptimizer, Debian's libmeshoptimizer-dev).
// What they decode becomes plain buffers, buffer views and accessors, so that the rest of the
// reader sees an uncompressed file. A build without a library does not read its extension
// (the reader then refuses a file that requires it, by name).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace svetlo {

/// The glTF or GLB file `path` as tinygltf (2.7, built without Draco) can load it, where it
/// uses compression this build decodes: EXT_meshopt_compression's fallback buffers (no uri:
/// their bytes exist only compressed) given a data: URI of 3 zero bytes, since tinygltf
/// reads every buffer; a Draco primitive's `indices` left out, since tinygltf wants their
/// buffer view, which only the Draco stream holds (decompress_geometry makes the indices).
/// Empty when nothing needs it: tinygltf then reads the file itself.
std::vector<unsigned char> tinygltf_loadable(const std::filesystem::path& path, bool binary);

/// Whether this build decodes the extension `name` (one of the two above).
bool decodes_compression(const std::string& name);

/// Every primitive with KHR_draco_mesh_compression decoded into new buffers, its attributes'
/// and indices' accessors pointed at them (floats, and 32-bit indices); every buffer view
/// with EXT_meshopt_compression decoded into a new buffer, filters applied. Throws
/// std::runtime_error naming the mesh, primitive or buffer view that does not decode.
void decompress_geometry(tinygltf::Model& model);

}  // namespace svetlo
