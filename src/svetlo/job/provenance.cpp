#include "svetlo/job/provenance.h"

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"

#ifndef SVETLO_VERSION
#define SVETLO_VERSION "unknown"
#endif
#ifndef SVETLO_COMMIT
#define SVETLO_COMMIT "unknown"
#endif

namespace svetlo {

nlohmann::json make_provenance(const RunRecord& run, const Scene& scene,
                               const RenderOptions& options, const RenderStats& stats, int spp) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::path absolute = fs::weakly_canonical(fs::absolute(run.scene_file, ec), ec);
    const Crop crop = film_window(scene, options);
    return {
        {"version", SVETLO_VERSION},
        {"commit", SVETLO_COMMIT},
        {"command", run.command},
        {"scene_file", absolute.string()},
        {"scene_sha256", run.scene_sha256},
        {"scene", run.scene},
        {"engine", scene.render.engine},
        {"image", run.image},
        {"spp", spp},
        {"seed", scene.render.seed},
        {"threads", options.threads},
        {"seconds", stats.seconds},
        {"setup_seconds", stats.setup_seconds},
        {"crop", {crop.x0, crop.x1, crop.y0, crop.y1}},
        {"full_resolution", {scene.film.width, scene.film.height}},
        {"processes", run.processes},
        {"interrupted", run.interrupted},
    };
}

nlohmann::json read_provenance(const std::filesystem::path& path, const std::string& where) {
    std::string text = read_image_metadata(path, where);
    if (text.empty()) {
        throw Error(path.string(), where,
                    "the image has no provenance (svetlo writes it into every image it makes)");
    }
    nlohmann::json p = nlohmann::json::parse(text, nullptr, false);
    if (!p.is_object()) throw Error(path.string(), where, "its provenance is not a JSON object");
    return p;
}

namespace {

std::vector<int> int_array(const nlohmann::json& p, const char* key, size_t count,
                           const std::string& file) {
    auto it = p.find(key);
    std::vector<int> out;
    if (it != p.end() && it->is_array() && it->size() == count) {
        for (const auto& v : *it) {
            if (!v.is_number_integer()) break;
            out.push_back(v.get<int>());
        }
    }
    if (out.size() != count) {
        throw Error(file, std::string("provenance.") + key,
                    "expected " + std::to_string(count) + " whole numbers");
    }
    return out;
}

}  // namespace

Crop provenance_crop(const nlohmann::json& p, const std::string& file) {
    std::vector<int> c = int_array(p, "crop", 4, file);
    return {c[0], c[1], c[2], c[3]};
}

std::pair<int, int> provenance_resolution(const nlohmann::json& p, const std::string& file) {
    std::vector<int> r = int_array(p, "full_resolution", 2, file);
    return {r[0], r[1]};
}

}  // namespace svetlo
