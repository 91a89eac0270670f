// SHA-256 (FIPS 180-4) of a file's bytes, as lowercase hex: the provenance's scene_sha256.
// OpenSSL's where it is built; elsewhere (the browser's WebAssembly) the plain statement of
// the standard, which the tests hold to OpenSSL's.
#pragma once

#include <filesystem>
#include <string>

namespace svetlo {

/// The digest of the bytes of `path`; throws std::runtime_error when it cannot be read.
std::string sha256_file(const std::filesystem::path& path);

/// The digest of `bytes`.
std::string sha256_hex(const std::string& bytes);

/// The same, computed as FIPS 180-4 section 6.2 states it.
std::string sha256_hex_plain(const std::string& bytes);

}  // namespace svetlo
