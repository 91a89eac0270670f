#include "svetlo/scene/json_node.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace svetlo {

namespace {

std::string type_name(const nlohmann::json& v) {
    switch (v.type()) {
        case nlohmann::json::value_t::null:
            return "null";
        case nlohmann::json::value_t::object:
            return "an object";
        case nlohmann::json::value_t::array:
            return "an array";
        case nlohmann::json::value_t::string:
            return "a string";
        case nlohmann::json::value_t::boolean:
            return "a boolean";
        default:
            return "a number";
    }
}

std::string format_number(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

}  // namespace

void JsonNode::fail(const std::string& what) const {
    throw Error(file_, path_.empty() ? "(top level)" : path_, what);
}

void JsonNode::expect_object(std::initializer_list<std::string_view> allowed) const {
    if (!value_->is_object()) fail("must be an object, not " + type_name(*value_));
    for (const auto& [key, value] : value_->items()) {
        if (!key.empty() && key[0] == '_') continue;
        bool known = false;
        for (std::string_view a : allowed) known = known || key == a;
        if (!known) {
            std::string list;
            for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            JsonNode(value, file_, path_.empty() ? key : path_ + "." + key)
                .fail("unknown key (expected one of: " + list + ")");
        }
    }
}

bool JsonNode::has(const std::string& key) const {
    return value_->is_object() && value_->contains(key);
}

JsonNode JsonNode::at(const std::string& key) const {
    std::string child = path_.empty() ? key : path_ + "." + key;
    if (!value_->is_object()) fail("must be an object, not " + type_name(*value_));
    auto it = value_->find(key);
    if (it == value_->end()) JsonNode(*value_, file_, child).fail("missing key");
    return JsonNode(*it, file_, child);
}

std::optional<JsonNode> JsonNode::find(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return at(key);
}

size_t JsonNode::size() const {
    if (!value_->is_array()) fail("must be an array, not " + type_name(*value_));
    return value_->size();
}

JsonNode JsonNode::at(size_t index) const {
    if (!value_->is_array()) fail("must be an array, not " + type_name(*value_));
    if (index >= value_->size()) fail("has no element " + std::to_string(index));
    return JsonNode((*value_)[index], file_, path_ + "[" + std::to_string(index) + "]");
}

double JsonNode::as_number() const {
    if (!value_->is_number()) fail("must be a number, not " + type_name(*value_));
    double x = value_->get<double>();
    if (!std::isfinite(x)) fail("must be a finite number");
    return x;
}

float JsonNode::as_float() const {
    double x = as_number();
    if (std::abs(x) > static_cast<double>(std::numeric_limits<float>::max())) {
        fail("must be at most 3.4e38 in magnitude, the range of a float (is " + format_number(x) +
             ")");
    }
    return static_cast<float>(x);
}

float JsonNode::as_positive() const {
    double x = as_number();
    if (!(x > 0.0)) fail("must be > 0 (is " + format_number(x) + ")");
    return as_float();
}

float JsonNode::as_non_negative() const {
    double x = as_number();
    if (x < 0.0) fail("must be >= 0 (is " + format_number(x) + ")");
    return as_float();
}

float JsonNode::as_in_range(double lo, double hi) const {
    double x = as_number();
    if (x < lo || x > hi) {
        fail("must be in [" + format_number(lo) + ", " + format_number(hi) + "] (is " +
             format_number(x) + ")");
    }
    return static_cast<float>(x);
}

long long JsonNode::as_integer(long long lo, long long hi) const {
    double x = as_number();
    if (std::floor(x) != x) fail("must be a whole number (is " + format_number(x) + ")");
    if (x < static_cast<double>(lo) || x > static_cast<double>(hi)) {
        fail("must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (is " +
             format_number(x) + ")");
    }
    return static_cast<long long>(x);
}

bool JsonNode::as_bool() const {
    if (!value_->is_boolean()) fail("must be true or false, not " + type_name(*value_));
    return value_->get<bool>();
}

std::string JsonNode::as_string() const {
    if (!value_->is_string()) fail("must be a string, not " + type_name(*value_));
    return value_->get<std::string>();
}

std::string JsonNode::as_choice(std::initializer_list<std::string_view> choices) const {
    std::string s = as_string();
    std::string list;
    for (std::string_view c : choices) {
        if (s == c) return s;
        list += (list.empty() ? "" : ", ") + std::string(c);
    }
    fail("unknown value '" + s + "' (expected one of: " + list + ")");
}

vec3 JsonNode::as_vec3() const {
    if (!value_->is_array() || value_->size() != 3) fail("must be an array of 3 numbers");
    return vec3(at(size_t{0}).as_float(), at(size_t{1}).as_float(), at(size_t{2}).as_float());
}

vec3 JsonNode::as_direction() const {
    vec3 v = as_vec3();
    float len = glm::length(v);
    if (!(len > 1e-20f) || !std::isfinite(len)) fail("must be a non-zero vector");
    return v / len;
}

Color JsonNode::as_color() const {
    if (value_->is_number()) return Color(as_non_negative());
    if (!value_->is_array() || value_->size() != 3) {
        fail("must be a colour: a number or an array of 3 numbers");
    }
    return Color(at(size_t{0}).as_non_negative(), at(size_t{1}).as_non_negative(),
                 at(size_t{2}).as_non_negative());
}

float JsonNode::get_float(const std::string& key, float fallback) const {
    auto node = find(key);
    return node ? node->as_float() : fallback;
}

Color JsonNode::get_color(const std::string& key, Color fallback) const {
    auto node = find(key);
    return node ? node->as_color() : fallback;
}

}  // namespace svetlo
