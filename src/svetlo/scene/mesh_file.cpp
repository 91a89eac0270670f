#include "svetlo/scene/mesh_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "svetlo/core/image_io.h"
#include "svetlo/core/input_file.h"

namespace svetlo {
namespace fs = std::filesystem;

MeshFile read_mesh_file(const fs::path& path, const FileScope& files) {
    require_input_file(path);
    const std::string ext = lower_extension(path);
    MeshFile file;
    if (ext == ".obj") {
        file = read_obj(path, files);
    } else if (ext == ".ply") {
        file = read_ply(path);
    } else if (ext == ".gltf" || ext == ".glb") {
        file = read_gltf(path, files);
    } else {
        throw std::runtime_error("unknown mesh format '" + ext + "' (use .obj, .ply, .gltf, .glb)");
    }
    validate_mesh(file.mesh);
    for (const MeshFile::Shared& s : file.shared) validate_mesh(s.mesh);
    return file;
}

Bounds3 file_bounds(const MeshFile& file) {
    Bounds3 b;
    for (const vec3& p : file.mesh.positions) b.extend(p);
    for (const MeshFile::Shared& s : file.shared)
        for (const mat4& m : s.places)
            for (const vec3& p : s.mesh.positions) b.extend(vec3(m * vec4(p, 1.0f)));
    return b;
}

Color file_color(double r, double g, double b, const std::string& what) {
    const double max = std::numeric_limits<float>::max();
    for (double c : {r, g, b}) {
        if (!(c >= 0.0 && c <= max)) {  // also false for NaN
            char value[96];
            std::snprintf(value, sizeof value, "(%g, %g, %g)", r, g, b);
            throw std::runtime_error(what + " " + value +
                                     ": a colour must be finite and >= 0 in every component");
        }
    }
    return Color(static_cast<float>(r), static_cast<float>(g), static_cast<float>(b));
}

void validate_mesh(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw std::runtime_error("index count is not a multiple of 3");
    for (size_t k = 0; k < mesh.positions.size(); ++k) {
        const vec3& p = mesh.positions[k];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw std::runtime_error("vertex " + std::to_string(k) + " is not finite");
        }
    }
    for (size_t k = 0; k < mesh.indices.size(); ++k) {
        if (mesh.indices[k] >= mesh.positions.size()) {
            throw std::runtime_error("triangle " + std::to_string(k / 3) + " refers to vertex " +
                                     std::to_string(mesh.indices[k]) + " of " +
                                     std::to_string(mesh.positions.size()));
        }
    }
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
        throw std::runtime_error("normal count differs from position count");
    }
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) {
        throw std::runtime_error("uv count differs from position count");
    }
    if (!mesh.uvs1.empty() && mesh.uvs1.size() != mesh.positions.size()) {
        throw std::runtime_error("second uv set's count differs from position count");
    }
    if (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size()) {
        throw std::runtime_error("vertex colour count differs from position count");
    }
    if (!mesh.tangents.empty() && mesh.tangents.size() != mesh.positions.size()) {
        throw std::runtime_error("tangent count differs from position count");
    }
}

void compute_vertex_normals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), vec3(0.0f));
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        // The cross product's length is twice the area: an area-weighted average.
        vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a],
                            mesh.positions[c] - mesh.positions[a]);
        mesh.normals[a] += n;
        mesh.normals[b] += n;
        mesh.normals[c] += n;
    }
    for (vec3& n : mesh.normals) {
        float len = glm::length(n);
        n = len > 0.0f ? n / len : vec3(0.0f, 0.0f, 1.0f);
    }
}

}  // namespace svetlo
