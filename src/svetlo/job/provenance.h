// Provenance: how an image was made, carried inside it (docs/provenance.md). A JSON object with the
// program's version and commit, the command line, the scene file and its SHA-256, the whole
// effective scene after every override, the engine, spp reached, seed, threads, seconds, the crop
// and the full resolution; `svetlo info IMAGE` prints it and `svetlo reproduce` renders it again.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "svetlo/scene/renderer.h"

namespace svetlo {

/// What a render command knows of its run beyond the scene and the engine's options.
struct RunRecord {
    std::vector<std::string> command;  // the argument list, argv[0] first
    std::filesystem::path scene_file;
    std::string scene_sha256;     // of the scene file's bytes when it was read
    nlohmann::json scene;         // the effective scene
    bool interrupted = false;     // SIGINT or SIGTERM ended it early
    std::string image = "color";  // or the AOV's name
    int processes = 1;            // MPI ranks that rendered it (docs/distributed.md)
};

/// The provenance object of an image of `run`, rendered from `scene` with `options` (engine,
/// seed, threads, crop and film come from these), whose render reported `stats` and reached
/// `spp`.
nlohmann::json make_provenance(const RunRecord& run, const Scene& scene,
                               const RenderOptions& options, const RenderStats& stats, int spp);

/// The provenance in an image file; throws Error(path, where, ...) when the file has none
/// or it is not a JSON object.
nlohmann::json read_provenance(const std::filesystem::path& path, const std::string& where);

/// The crop [X0, X1, Y0, Y1] and full resolution [W, H] a provenance records, checked.
Crop provenance_crop(const nlohmann::json& p, const std::string& file);
std::pair<int, int> provenance_resolution(const nlohmann::json& p, const std::string& file);

}  // namespace svetlo
