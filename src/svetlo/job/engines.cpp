#include "svetlo/job/engines.h"

#include <algorithm>
#include <functional>
#include <utility>

#include "svetlo/core/error.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"

namespace svetlo {

namespace {

using Factory = std::function<std::unique_ptr<Renderer>()>;

const std::vector<std::pair<std::string, Factory>>& factories() {
    static const std::vector<std::pair<std::string, Factory>> table = {
        {"raster", [] { return std::make_unique<RasterRenderer>(); }},
        {"whitted", [] { return std::make_unique<WhittedRenderer>(); }},
        {"path", [] { return std::make_unique<PathRenderer>(); }},
        {"radiosity", [] { return std::make_unique<RadiosityRenderer>(); }},
    };
    return table;
}

/// Names joined as a reader lists them: "a", "a or b", "a, b or c".
std::string either(const std::vector<std::string>& names) {
    std::string out;
    for (size_t k = 0; k < names.size(); ++k)
        out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
    return out;
}

}  // namespace

const std::vector<Capabilities>& engine_capabilities() {
    static const std::vector<Capabilities> all = [] {
        std::vector<Capabilities> out;
        for (const auto& [name, make] : factories()) out.push_back(make()->capabilities());
        return out;
    }();
    return all;
}

const Capabilities& capabilities_of(const std::string& name, const std::string& file) {
    for (const Capabilities& c : engine_capabilities())
        if (c.name == name) return c;
    std::string available;
    for (const Capabilities& c : engine_capabilities())
        available += (available.empty() ? "" : ", ") + c.name;
    throw Error(file, "render.engine",
                "engine '" + name +
                    "' is not available in this version of svetlo (available: " + available + ")");
}

std::unique_ptr<Renderer> make_renderer(const std::string& name, const std::string& file) {
    capabilities_of(name, file);  // an unknown engine: one line naming render.engine
    for (const auto& [known, make] : factories())
        if (known == name) return make();
    return nullptr;  // not reached
}

std::string engines_with(const std::function<bool(const Capabilities&)>& what) {
    std::vector<std::string> names;
    for (const Capabilities& c : engine_capabilities())
        if (what(c)) names.push_back(c.name);
    return either(names);
}

std::string debug_aov_refusal(const Scene& scene, const std::string& name) {
    const std::vector<std::string> known = debug_aov_names();
    if (std::find(known.begin(), known.end(), name) == known.end()) return {};
    auto makes = [&](const Capabilities& c) {
        return std::find(c.debug_aovs.begin(), c.debug_aovs.end(), name) != c.debug_aovs.end();
    };
    const std::optional<ShadowTechnique> technique = debug_aov_technique(name);
    if (makes(capabilities_of(scene.render.engine, scene.path.string())) &&
        (!technique || scene.render.shadows == *technique))
        return {};
    std::string why = "needs render.engine " + engines_with(makes);
    if (technique)
        why += " with render.shadows " + std::string(name_of(kShadowTechniques, *technique));
    return why;
}

}  // namespace svetlo
