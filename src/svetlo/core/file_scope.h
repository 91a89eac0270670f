// Where the files that a scene or a model names may lie (docs/viewer.md, "What the server
// reads"). On the command line anywhere; under `svetlo serve` inside the served folder, so
// that neither a scene, nor an override in a link, nor a model's own references lead the
// server to a file of the disk it does not serve. One rule, used by every reader that opens
// a file another file names: meshes, textures, materials, buffers, environments.
#pragma once

#include <filesystem>
#include <string>

namespace svetlo {

class FileScope {
public:
    /// Anywhere: the command line's scope.
    FileScope() = default;
    /// Inside `root` alone (made canonical here).
    explicit FileScope(const std::filesystem::path& root);

    bool confined() const { return !root_.empty(); }
    const std::filesystem::path& root() const { return root_; }

    /// The file `name` as named from the folder `base` (a relative name is taken from `base`,
    /// an absolute one as it is). Throws std::runtime_error("'NAME' is outside the served
    /// folder") when the scope is confined and the file, links followed, lies outside it.
    std::filesystem::path resolve(const std::filesystem::path& base, const std::string& name) const;

    /// `text` with the root's own path taken out ("/srv/scenes/a.json: ..." becomes
    /// "a.json: ..."): what a client of the server is shown.
    std::string relative_text(std::string text) const;

private:
    std::filesystem::path root_;  // canonical; empty: anywhere
};

}  // namespace svetlo
