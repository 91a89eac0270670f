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

namespace {

/// The rasterizer's technique: its shading (unless Phong, its own), its visibility (unless the
/// z-buffer) and its shadows.
std::string raster_technique(const RenderSettings& r) {
    std::vector<std::string> parts;
    switch (r.shading) {
        case ShadingMode::Flat:
            parts.push_back("flat shading");
            break;
        case ShadingMode::Gouraud:
            parts.push_back("Gouraud shading");
            break;
        case ShadingMode::Phong:
            break;
        case ShadingMode::Depth:
        case ShadingMode::Normal:
        case ShadingMode::Overdraw:  // a view of the buffers: no light, no shadows
            return std::string(name_of(kShadingModes, r.shading)) + " view";
    }
    if (r.raster.visibility == VisibilityMethod::Painter) parts.push_back("painter's algorithm");
    switch (r.shadows) {
        case ShadowTechnique::None:
            parts.push_back("no shadows");
            break;
        case ShadowTechnique::Planar:
            parts.push_back("planar shadows");
            break;
        case ShadowTechnique::Volume:
            parts.push_back(
                r.shadow_teaching.volume_count == VolumeCount::ZFail   ? "shadow volume, z-fail"
                : r.shadow_teaching.volume_count == VolumeCount::ZPass ? "shadow volume, z-pass"
                                                                       : "shadow volume");
            break;
        case ShadowTechnique::Map:
            parts.push_back(r.shadow_map.filter == ShadowFilter::Pcss  ? "shadow map, PCSS"
                            : r.shadow_map.filter == ShadowFilter::Pcf ? "shadow map, PCF"
                                                                       : "shadow map");
            break;
        case ShadowTechnique::Raytraced:
            parts.push_back("ray-traced shadows");
            break;
    }
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : ", ") + p;
    return out;
}

}  // namespace

std::string technique_name(const RenderSettings& r) {
    if (r.engine == "raster") return raster_technique(r);
    if (r.engine == "whitted") return "Whitted ray tracing";
    if (r.engine == "path") {
        std::string out = "path tracing";
        if (r.guiding) out += ", guided";
        if (r.mis == MisMode::LightOnly) out += ", light sampling alone";
        if (r.mis == MisMode::BsdfOnly) out += ", BSDF sampling alone";
        if (r.caustics == CausticMode::Photons) out += ", photons";
        return out;
    }
    if (r.engine == "radiosity") {
        const RadiositySettings& s = r.radiosity;
        std::string out = s.solver == RadiositySolver::Progressive    ? "progressive radiosity"
                          : s.solver == RadiositySolver::Jacobi       ? "radiosity, Jacobi"
                          : s.solver == RadiositySolver::GaussSeidel  ? "radiosity, Gauss-Seidel"
                          : s.solver == RadiositySolver::Hierarchical ? "hierarchical radiosity"
                                                                      : "radiosity";
        if (s.form_factors == FormFactorMethod::Hemicube) out += ", hemicubes";
        if (s.form_factors == FormFactorMethod::Raycast) out += ", ray-cast form factors";
        return out;
    }
    return r.engine;
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
