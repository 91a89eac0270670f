// Readers for triangle-mesh files: OBJ with its MTL (tinyobjloader), PLY (ASCII and binary,
// svetlo's own reader) and glTF 2.0 with KHR_lights_punctual (tinygltf). Each returns the
// triangles in the file's object space, plus the materials and lights the file brings.
// Failures throw std::runtime_error with the file's own place ("line 12: ..."); the scene
// loader adds the scene file and the JSON path.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "svetlo/scene/scene.h"

namespace svetlo {

struct MeshFile {
    Mesh mesh;  // face_material indexes `materials` below, or is empty
    /// A glTF mesh that several nodes place, in its own space, and each node's transform to
    /// the file's space: the scene makes it a prototype and each node an instance
    /// (docs/real-scenes.md, "Instances"). `mesh` holds the meshes one node places, baked.
    struct Shared {
        Mesh mesh;
        std::vector<mat4> places;
    };
    std::vector<Shared> shared;
    std::vector<Material> materials;
    std::vector<std::string> material_names;
    std::vector<Light> lights;     // glTF punctual lights, in the file's space
    std::optional<Camera> camera;  // glTF: the first camera of the default scene
    // The textures the materials' ColorSources index (the loader moves them into the scene).
    std::vector<TextureImage> textures;
    // What was read but left out, one line each (a glTF's optional extension svetlo does not
    // read): the scene keeps them and the command line prints them as warnings.
    std::vector<std::string> warnings;
    // The glTF extensions the file uses (extensionsUsed), those svetlo ignores marked so.
    std::vector<std::string> extensions;
};

/// A colour read from a mesh file (MTL Kd, glTF baseColorFactor, a light's intensity...):
/// every component finite, >= 0 and within a float's range, as the scene's own colours.
/// Throws std::runtime_error naming `what` and the value otherwise.
Color file_color(double r, double g, double b, const std::string& what);

/// The bounds of everything the file places, in its space (`mesh`, and each shared mesh at
/// each of its places).
Bounds3 file_bounds(const MeshFile& file);

/// Reads .obj, .ply, .gltf or .glb by extension. The files it names in turn (an OBJ's MTL, a
/// glTF's buffers and images) must lie in `files`.
MeshFile read_mesh_file(const std::filesystem::path& path, const FileScope& files = {});

MeshFile read_obj(const std::filesystem::path& path, const FileScope& files = {});
MeshFile read_ply(const std::filesystem::path& path);
MeshFile read_gltf(const std::filesystem::path& path, const FileScope& files = {});

/// Checks a mesh for finite positions and in-range indices; throws std::runtime_error.
void validate_mesh(const Mesh& mesh);
/// Fills `mesh.normals` with area-weighted vertex normals (for `smooth` meshes without them).
void compute_vertex_normals(Mesh& mesh);

}  // namespace svetlo
