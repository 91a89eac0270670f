// A request's query string read as a shared link is written (docs/viewer.md, "Links"):
// NAME=VALUE pairs split at their first '=', so that `set=render.shading=phong` keeps its
// KEY=VALUE whole, then percent-decoded ('+' a space, as browsers encode forms).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace svetlo {

class Query {
public:
    /// The query of a request target (`/api/render?scene=a.json&set=...`), or a query alone.
    explicit Query(std::string_view target);

    bool has(const std::string& name) const;
    /// The first value of `name`, or "" when it is absent.
    std::string get(const std::string& name) const;
    /// Every value of `name`, in order.
    std::vector<std::string> all(const std::string& name) const;

private:
    std::vector<std::pair<std::string, std::string>> params_;
};

/// `text` with its %XX escapes decoded and '+' made a space; a '%' not followed by two hex
/// digits is kept as it is.
std::string percent_decode(std::string_view text);

}  // namespace svetlo
