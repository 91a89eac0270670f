#include "svetlo/core/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>

namespace svetlo {

namespace fs = std::filesystem;

fs::path temporary_path(const fs::path& path) {
    std::random_device rd;
    fs::path tmp = path;
    tmp += ".tmp" + std::to_string(rd() % 1000000) + "." + std::to_string(::getpid());
    return tmp;
}

void write_file_atomically(const fs::path& path, const std::string& bytes) {
    const fs::path tmp = temporary_path(path);
    try {
        {
            std::ofstream out(tmp, std::ios::binary);
            if (!out) throw std::runtime_error(std::strerror(errno));
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
            if (!out.flush()) throw std::runtime_error("write failed");
        }
        fs::rename(tmp, path);
    } catch (const std::exception&) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
    }
}

}  // namespace svetlo
