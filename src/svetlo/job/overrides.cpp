#include "svetlo/job/overrides.h"

#include <algorithm>

#include "svetlo/core/error.h"
#include "svetlo/job/limits.h"

namespace svetlo {

std::vector<Override> parse_sets(const std::vector<std::string>& sets, const std::string& file) {
    std::vector<Override> out;
    for (const std::string& s : sets) {
        const size_t eq = s.find('=');
        if (eq == std::string::npos || eq == 0)
            throw Error(file, "--set " + s, "expected KEY=VALUE");
        out.push_back({s.substr(0, eq), s.substr(eq + 1)});
    }
    return out;
}

nlohmann::json scene_text_with_overrides(const std::string& text, const std::string& file,
                                         const std::vector<Override>& overrides) {
    nlohmann::json json;
    try {
        json = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw Error(file, "scene", e.what());
    }
    for (const Override& o : overrides) apply_override(json, o, file);
    return json;
}

void add_key_overrides(const std::string& file, const RequestKeys& keys,
                       const RequestKeyNames& names, std::vector<Override>& overrides,
                       const RequestLimits& limits) {
    if (!keys.engine.empty())
        overrides.push_back({"render.engine", nlohmann::json(keys.engine).dump()});
    auto number = [&](const std::string& text, const char* name, const char* key, long long lo,
                      long long hi) {
        if (!text.empty())
            overrides.push_back({key, std::to_string(flag_integer(file, name, text, lo, hi))});
    };
    number(keys.width, names.width, "film.width", 1, std::min(limits.side, kMaxFilmSide));
    number(keys.height, names.height, "film.height", 1, std::min(limits.side, kMaxFilmSide));
    number(keys.spp, names.spp, "render.spp", 1, std::min(limits.spp, kMaxSpp));
    number(keys.seed, names.seed, "render.seed", 0, kMaxSeed);
}

}  // namespace svetlo
