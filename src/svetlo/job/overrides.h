// A caller's request as scene overrides, by one rule for every caller (the command line, the
// viewer's links, Python, the web page): its `set` entries first, then the keys its flags or
// keywords stand for (they win), each checked with the ranges of the scene's keys and named in
// messages as that caller names it.
#pragma once

#include <string>
#include <vector>

#include "svetlo/job/limits.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {

/// `KEY=VALUE` strings (--set, a link's set=) as overrides, split at the first '='; the value
/// is read later as --set reads it (override_value). Throws Error naming `--set ENTRY` for an
/// entry without a key.
std::vector<Override> parse_sets(const std::vector<std::string>& sets, const std::string& file);

/// A scene given as JSON text (Python's, the web page's), named `file`, with `overrides`
/// applied in order; throws Error(file, "scene", ...) for text that is not JSON.
nlohmann::json scene_text_with_overrides(const std::string& text, const std::string& file,
                                         const std::vector<Override>& overrides);

/// The keys a caller may set beside `set`, as text (empty: not given).
struct RequestKeys {
    std::string engine;  // render.engine
    std::string width;   // film.width
    std::string height;  // film.height
    std::string spp;     // render.spp
    std::string seed;    // render.seed
};

/// The largest film side and samples a caller accepts: the scene keys' own ranges, or a
/// server's tighter ones (svetlo serve's, so that no client can hold the machine).
struct RequestLimits {
    long long side = kMaxFilmSide;
    long long spp = kMaxSpp;
};

/// How a caller names those keys in its messages.
struct RequestKeyNames {
    const char* engine;
    const char* width;
    const char* height;
    const char* spp;
    const char* seed;
};
inline constexpr RequestKeyNames kFlagNames{"-e", "-W", "-H", "--spp", "--seed"};
/// Python's keywords, the web page's options and the viewer's query parameters.
inline constexpr RequestKeyNames kKeywordNames{"engine", "width", "height", "spp", "seed"};

/// The request keys a caller gives by name, as `text(NAME)` finds them (empty: not given):
/// Python's keywords, the web page's options.
template <class Text>
RequestKeys request_keys(const RequestKeyNames& names, Text&& text) {
    return {text(names.engine), text(names.width), text(names.height), text(names.spp),
            text(names.seed)};
}

/// Appends the given keys to `overrides`, checked (whole numbers in the scene keys' ranges,
/// the film and samples within `limits`); throws Error(file, NAME, ...) naming the key as
/// `names` says.
void add_key_overrides(const std::string& file, const RequestKeys& keys,
                       const RequestKeyNames& names, std::vector<Override>& overrides,
                       const RequestLimits& limits = {});

}  // namespace svetlo
