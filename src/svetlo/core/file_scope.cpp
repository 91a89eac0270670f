#include "svetlo/core/file_scope.h"

#include <stdexcept>

namespace svetlo {

namespace fs = std::filesystem;

FileScope::FileScope(const fs::path& root) {
    std::error_code ec;
    root_ = fs::weakly_canonical(fs::absolute(root, ec), ec);
    if (ec || root_.empty()) root_ = fs::absolute(root).lexically_normal();
}

fs::path FileScope::resolve(const fs::path& base, const std::string& name) const {
    const fs::path path = base / name;
    if (!confined()) return path;
    // Links followed and ".." folded: the file where the system would open it.
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(fs::absolute(path, ec), ec);
    const fs::path inside = real.lexically_relative(root_);
    if (ec || name.find('\0') != std::string::npos || inside.empty() || *inside.begin() == "..")
        throw std::runtime_error("'" + name + "' is outside the served folder");
    return real;
}

std::string FileScope::relative_text(std::string text) const {
    if (!confined()) return text;
    const std::string prefix = root_.string() + "/";
    for (size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at))
        text.replace(at, prefix.size(), "");
    return text;
}

}  // namespace svetlo
