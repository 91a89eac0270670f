#include "svetlo/job/checkpoint.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "svetlo/core/atomic_file.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/input_file.h"
#include "svetlo/core/sha256.h"

namespace svetlo {

namespace {

// The file: the magic, the format's version, the key (64 hex digits), the passes (int32), the
// number of values (uint64), the values (doubles), then the SHA-256 (64 hex digits) of all
// that comes before it. Numbers are stored as the machine holds them (little-endian x86-64
// and arm64): a checkpoint resumes on the machine kind that wrote it.
constexpr char kMagic[8] = {'S', 'V', 'C', 'H', 'E', 'C', 'K', '1'};
constexpr size_t kHeader = sizeof kMagic + 64 + sizeof(int32_t) + sizeof(uint64_t);
constexpr size_t kDigest = 64;

/// What a checkpoint must match: the effective scene (every key, spp and seed among them), the
/// window and the AOVs asked for.
std::string run_key(const RenderJob& job, CheckpointFile::Layout layout) {
    const Crop c = film_window(job.scene, job.options);
    const std::string kind = layout == CheckpointFile::Layout::Tiles ? " tiles" : "";
    std::string text = "svetlo checkpoint 1" + kind + "\n" + job.run.scene.dump() + "\n" +
                       std::to_string(c.x0) + "," + std::to_string(c.x1) + "," +
                       std::to_string(c.y0) + "," + std::to_string(c.y1) + "\n";
    for (const std::string& a : job.options.aovs) text += "aov " + a + "\n";
    for (const std::string& a : job.options.debug_aovs) text += "debug " + a + "\n";
    return sha256_hex(text);
}

}  // namespace

CheckpointFile::CheckpointFile(std::string path, const RenderJob& job, Layout layout, bool writer)
    : path_(std::move(path)), key_(run_key(job, layout)) {
    const std::string where = "--checkpoint";
    if (std::filesystem::exists(path_)) {
        // A regular file, at most 8 GiB (an 8192² film's sums with every AOV).
        if (std::string problem = input_file_problem(path_, uintmax_t{8} << 30); !problem.empty())
            throw Error(path_, where, problem);
        std::string bytes(static_cast<size_t>(std::filesystem::file_size(path_)), '\0');
        std::ifstream in(path_, std::ios::binary);
        if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
            throw Error(path_, where, "cannot be read");
        if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
            throw Error(path_, where, "is not a svetlo checkpoint");
        if (bytes.size() < kHeader + kDigest ||
            sha256_hex(bytes.substr(0, bytes.size() - kDigest)) !=
                bytes.substr(bytes.size() - kDigest))
            throw Error(path_, where, "is corrupt or truncated (its checksum does not match)");
        if (bytes.compare(sizeof kMagic, 64, key_) != 0)
            throw Error(path_, where,
                        "was saved by a render of another scene or other settings; remove it "
                        "or give another file");
        int32_t passes = 0;
        uint64_t count = 0;
        std::memcpy(&passes, bytes.data() + sizeof kMagic + 64, sizeof passes);
        std::memcpy(&count, bytes.data() + sizeof kMagic + 64 + sizeof passes, sizeof count);
        if (passes < 1 || count != (bytes.size() - kHeader - kDigest) / sizeof(double) ||
            kHeader + count * sizeof(double) + kDigest != bytes.size())
            throw Error(path_, where, "is corrupt (its sizes do not agree)");
        passes_ = passes;
        state_.resize(count);
        std::memcpy(state_.data(), bytes.data() + kHeader, count * sizeof(double));
    }
    check_creatable(path_, where);
    callbacks_.restore = [this](std::vector<double>& state) {
        if (passes_ == 0) return 0;
        if (!state.empty() && state.size() != state_.size()) {
            throw Error(path_, "--checkpoint",
                        "holds " + std::to_string(state_.size()) + " values; this render has " +
                            std::to_string(state.size()));
        }
        state = state_;
        return passes_;
    };
    callbacks_.save = [this, writer](int passes, const std::vector<double>& state) {
        if (!writer) return;
        std::string bytes(kMagic, sizeof kMagic);
        bytes += key_;
        const auto p = static_cast<int32_t>(passes);
        const auto count = static_cast<uint64_t>(state.size());
        bytes.append(reinterpret_cast<const char*>(&p), sizeof p);
        bytes.append(reinterpret_cast<const char*>(&count), sizeof count);
        bytes.append(reinterpret_cast<const char*>(state.data()), state.size() * sizeof(double));
        bytes += sha256_hex(bytes);
        try {
            write_file_atomically(path_, bytes);
        } catch (const std::exception& e) {
            throw Error(path_, "--checkpoint", std::string("cannot write: ") + e.what());
        }
    };
}

}  // namespace svetlo
