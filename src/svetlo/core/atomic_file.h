// Files written whole or not at all: the bytes go to a temporary name beside the target (so
// that the rename stays on one file system) and are renamed over it only when complete. A
// failed write never leaves a partial or damaged file, and an existing one stays as it was.
#pragma once

#include <filesystem>
#include <string>

namespace svetlo {

/// A temporary name in `path`'s folder: `path.tmpNNNNNN.PID`.
std::filesystem::path temporary_path(const std::filesystem::path& path);

/// Writes `bytes` to `path` through a temporary file; throws std::runtime_error (and removes
/// the temporary file) when it cannot.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace svetlo
