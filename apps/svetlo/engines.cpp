#include "engines.h"

#include <functional>
#include <map>

#include "svetlo/core/error.h"
#include "svetlo/pt/path_tracer.h"
#include "svetlo/radiosity/radiosity_engine.h"
#include "svetlo/raster/raster_engine.h"
#include "svetlo/rt/whitted.h"

namespace svetlo {

std::unique_ptr<Renderer> make_renderer(const std::string& name, const std::string& file) {
    static const std::map<std::string, std::function<std::unique_ptr<Renderer>()>> factories = {
        {"raster", [] { return std::make_unique<RasterRenderer>(); }},
        {"whitted", [] { return std::make_unique<WhittedRenderer>(); }},
        {"path", [] { return std::make_unique<PathRenderer>(); }},
        {"radiosity", [] { return std::make_unique<RadiosityRenderer>(); }},
    };
    auto it = factories.find(name);
    if (it == factories.end()) {
        throw Error(file, "render.engine",
                    "engine '" + name +
                        "' is not available in this version of svetlo "
                        "(available: raster, whitted, path, radiosity)");
    }
    return it->second();
}

}  // namespace svetlo
