// load_scene(): reads a scene file (JSON, ../docs/scene-format.md), applies the command
// line's overrides and validates every key. Any problem throws svetlo::Error naming the file
// and the JSON path; nothing is allocated from a size the file states before it is checked.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "svetlo/scene/file_cache.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// One `--set KEY=VALUE`: a dotted path (`lights.0.intensity`) and its value, read as JSON
/// when it parses as JSON and as a string otherwise.
struct Override {
    std::string key;
    std::string value;
};

/// Largest film, in pixels, that svetlo accepts (8192 x 8192); larger ones are refused
/// before anything is allocated.
inline constexpr long long kMaxFilmPixels = 8192LL * 8192LL;
/// The ranges of the film's sides, of samples per pixel and of seeds (the flags that stand for
/// these keys check the same ranges).
inline constexpr long long kMaxFilmSide = 65536;
inline constexpr long long kMaxSpp = 1LL << 20;
/// Photons emitted per pass (render.photons.count). A pass stores at most four per photon
/// emitted, 48 bytes each: at most 768 MiB.
inline constexpr long long kMaxPhotons = 1LL << 22;
inline constexpr long long kMaxSeed = 1LL << 53;  // seeds are exact as JSON numbers (doubles)

Scene load_scene(const std::filesystem::path& path, const std::vector<Override>& overrides = {});

/// The effective scene: the file's JSON with every override applied, in order (what
/// load_scene builds the Scene from, and what an image's provenance records). A model file
/// (.gltf, .glb, .obj, .ply) is a scene of its own (model_scene.h), read through `meshes`
/// when given, within `files`.
nlohmann::json effective_scene_json(const std::filesystem::path& path,
                                    const std::vector<Override>& overrides,
                                    FileCache* meshes = nullptr, const FileScope& files = {});

/// Builds a Scene from JSON already in memory; `path` names it in messages and anchors
/// relative paths. Mesh files and images (textures, the environment) are read through
/// `meshes` (a FileCache) when given (the renders of one command share them), else each once for
/// this scene. Every file the scene names must lie in `files` (svetlo serve: the served folder).
Scene scene_from_json(const nlohmann::json& root, const std::filesystem::path& path,
                      FileCache* meshes = nullptr, const FileScope& files = {});

/// Parses a scene file, reporting syntax errors with line and column.
nlohmann::json read_scene_json(const std::filesystem::path& path);

/// The value of an override as --set reads it: JSON when `text` parses as JSON, else the
/// string itself (`phong`, `"phong"` and `[1,2,3]` are read alike by the command line, a
/// viewer link and Python).
nlohmann::json override_value(const std::string& text);

/// Applies one override to a scene's JSON; throws Error for a path that cannot exist.
void apply_override(nlohmann::json& root, const Override& o, const std::string& file);

}  // namespace svetlo
