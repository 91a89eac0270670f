#include "svetlo/job/limits.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "svetlo/core/error.h"

namespace svetlo {

namespace {

/// The text as given, cut short: a 309-digit number is not worth echoing whole.
std::string shown(const std::string& text) {
    return text.size() > 24 ? text.substr(0, 24) + "..." : text;
}

}  // namespace

long long flag_integer(const std::string& file, const std::string& flag, const std::string& text,
                       long long lo, long long hi) {
    char* end = nullptr;
    errno = 0;
    long long value = std::strtoll(text.c_str(), &end, 10);
    bool whole = !text.empty() && end == text.c_str() + text.size() &&
                 text.find_first_of(" \t") == std::string::npos;
    if (!whole) throw Error(file, flag, "must be a whole number (is '" + shown(text) + "')");
    if (errno == ERANGE || value > hi) {
        throw Error(file, flag, "must be <= " + std::to_string(hi) + " (is " + shown(text) + ")");
    }
    if (value < lo)
        throw Error(file, flag, "must be >= " + std::to_string(lo) + " (is " + shown(text) + ")");
    return value;
}

double flag_seconds(const std::string& file, const std::string& flag, const std::string& text) {
    if (text.empty()) return 0.0;
    char* end = nullptr;
    double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || text.find_first_of(" \t") != std::string::npos ||
        !std::isfinite(value)) {
        throw Error(file, flag, "must be a number of seconds (is '" + shown(text) + "')");
    }
    if (!(value > 0.0)) throw Error(file, flag, "must be > 0 (is " + shown(text) + ")");
    if (value > kMaxSeconds)
        throw Error(file, flag, "must be <= 604800, a week (is " + shown(text) + ")");
    return value;
}

}  // namespace svetlo
