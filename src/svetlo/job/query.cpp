#include "svetlo/job/query.h"

namespace svetlo {

namespace {

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

}  // namespace

std::string percent_decode(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (size_t k = 0; k < text.size(); ++k) {
        const char c = text[k];
        if (c == '+') {
            out += ' ';
        } else if (c == '%' && k + 2 < text.size() && hex_digit(text[k + 1]) >= 0 &&
                   hex_digit(text[k + 2]) >= 0) {
            out += static_cast<char>(hex_digit(text[k + 1]) * 16 + hex_digit(text[k + 2]));
            k += 2;
        } else {
            out += c;
        }
    }
    return out;
}

Query::Query(std::string_view target) {
    if (const size_t mark = target.find('?'); mark != std::string_view::npos)
        target.remove_prefix(mark + 1);
    else if (target.find('=') == std::string_view::npos)
        target = {};  // a path alone
    if (const size_t hash = target.find('#'); hash != std::string_view::npos)
        target = target.substr(0, hash);
    while (!target.empty()) {
        const size_t amp = target.find('&');
        const std::string_view pair = target.substr(0, amp);
        target = amp == std::string_view::npos ? std::string_view{} : target.substr(amp + 1);
        if (pair.empty()) continue;
        const size_t eq = pair.find('=');
        params_.emplace_back(
            percent_decode(pair.substr(0, eq)),
            eq == std::string_view::npos ? "" : percent_decode(pair.substr(eq + 1)));
    }
}

bool Query::has(const std::string& name) const {
    for (const auto& [key, value] : params_)
        if (key == name) return true;
    return false;
}

std::string Query::get(const std::string& name) const {
    for (const auto& [key, value] : params_)
        if (key == name) return value;
    return {};
}

std::vector<std::string> Query::all(const std::string& name) const {
    std::vector<std::string> out;
    for (const auto& [key, value] : params_)
        if (key == name) out.push_back(value);
    return out;
}

}  // namespace svetlo
