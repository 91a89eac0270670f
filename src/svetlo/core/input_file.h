// Every file svetlo reads (scenes, meshes, materials, glTF buffers, images) must be a regular
// file of a bounded size: a device (/dev/zero), a pipe or a huge file is refused before a byte
// is read, with a message that says which.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace svetlo {

/// The largest file svetlo reads (1 GiB), and the largest scene file (64 MiB of JSON).
inline constexpr uintmax_t kMaxInputBytes = uintmax_t{1} << 30;
inline constexpr uintmax_t kMaxSceneBytes = uintmax_t{64} << 20;

/// Why `path` cannot be read ("no such file", "is a directory", "is not a regular file (a
/// device, a pipe or a socket)", "is 2048 MiB, more than the limit of 1024 MiB"), or an empty
/// string when it can.
std::string input_file_problem(const std::filesystem::path& path,
                               uintmax_t max_bytes = kMaxInputBytes);

/// Throws std::runtime_error(input_file_problem) when there is one.
void require_input_file(const std::filesystem::path& path, uintmax_t max_bytes = kMaxInputBytes);

/// The file's bytes, read whole after require_input_file; std::runtime_error when it cannot.
std::vector<unsigned char> read_input_file(const std::filesystem::path& path,
                                           uintmax_t max_bytes = kMaxInputBytes);

}  // namespace svetlo
