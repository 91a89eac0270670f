// A validating view of one JSON value that knows its place in the scene file. Every read
// checks type, finiteness and range, and every failure becomes the one-line error
// `FILE: objects[3].radius: must be > 0`. This is svetlo's schema: the loader states for each
// object which keys it takes, which are required and what values they admit.
#pragma once

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "svetlo/core/error.h"
#include "svetlo/core/math.h"

namespace svetlo {

class JsonNode {
public:
    JsonNode(const nlohmann::json& value, std::string file, std::string path)
        : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

    const std::string& path() const { return path_; }
    const std::string& file() const { return file_; }
    const nlohmann::json& raw() const { return *value_; }

    [[noreturn]] void fail(const std::string& what) const;

    bool is_object() const { return value_->is_object(); }
    bool is_array() const { return value_->is_array(); }
    bool is_number() const { return value_->is_number(); }
    bool is_string() const { return value_->is_string(); }

    /// Requires an object whose keys are all in `allowed` (keys starting with '_' are
    /// comments and always allowed).
    void expect_object(std::initializer_list<std::string_view> allowed) const;
    bool has(const std::string& key) const;
    /// The member `key`; fails with "missing key" when absent.
    JsonNode at(const std::string& key) const;
    std::optional<JsonNode> find(const std::string& key) const;
    size_t size() const;              // of an array
    JsonNode at(size_t index) const;  // of an array

    double as_number() const;  // finite
    /// A number that a float represents: finite, and at most kMaxFloat in magnitude.
    float as_float() const;
    float as_positive() const;                      // > 0
    float as_non_negative() const;                  // >= 0
    float as_in_range(double lo, double hi) const;  // in [lo, hi]
    long long as_integer(long long lo, long long hi) const;
    bool as_bool() const;
    std::string as_string() const;
    /// One of `choices`; fails listing them.
    std::string as_choice(std::initializer_list<std::string_view> choices) const;
    /// One of a closed set, by name: `names` pairs each name with its value.
    template <class E, size_t N>
    E as_enum(const std::pair<std::string_view, E> (&names)[N]) const {
        std::string s = as_string();
        std::string list;
        for (const auto& [name, value] : names) {
            if (s == name) return value;
            list += (list.empty() ? "" : ", ") + std::string(name);
        }
        fail("unknown value '" + s + "' (expected one of: " + list + ")");
    }
    vec3 as_vec3() const;
    vec3 as_direction() const;  // non-zero, returned normalised
    /// A colour: one number (grey) or [r, g, b], each finite and >= 0.
    Color as_color() const;

    // Shorthands for optional members with defaults.
    float get_float(const std::string& key, float fallback) const;
    Color get_color(const std::string& key, Color fallback) const;

private:
    const nlohmann::json* value_;
    std::string file_;
    std::string path_;
};

}  // namespace svetlo
