#include "svetlo/core/input_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "svetlo/core/large_array.h"

namespace svetlo {

namespace fs = std::filesystem;

std::string input_file_problem(const fs::path& path, uintmax_t max_bytes) {
    std::error_code ec;
    fs::file_status status = fs::status(path, ec);  // follows symbolic links
    if (ec || !fs::exists(status)) return "no such file";
    if (fs::is_directory(status)) return "is a directory";
    if (!fs::is_regular_file(status)) return "is not a regular file (a device, a pipe or a socket)";
    uintmax_t size = fs::file_size(path, ec);
    if (ec) return "cannot read its size: " + ec.message();
    if (size > max_bytes) {
        return "is " + std::to_string(size >> 20) + " MiB, more than the limit of " +
               std::to_string(max_bytes >> 20) + " MiB";
    }
    return {};
}

void require_input_file(const fs::path& path, uintmax_t max_bytes) {
    std::string problem = input_file_problem(path, max_bytes);
    if (!problem.empty()) throw std::runtime_error(problem);
}

std::vector<unsigned char> read_input_file(const fs::path& path, uintmax_t max_bytes) {
    require_input_file(path, max_bytes);
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> bytes = large_buffer(fs::file_size(path));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!in) throw std::runtime_error(std::string("cannot read it: ") + std::strerror(errno));
    return bytes;
}

}  // namespace svetlo
