// --checkpoint FILE (docs/distributed.md): a progressive render's accumulators and
// the passes they hold, saved after every pass, atomically (a temporary file, then a rename),
// with the key of the run they belong to: a hash of the effective scene and the settings that
// change its pixels. The same command with the same FILE resumes where the last save left,
// and its image is bit for bit an uninterrupted run's. A file of another run, or one that is
// corrupt or truncated, is refused with one line before the render starts.
#pragma once

#include <string>
#include <vector>

#include "render_job.h"

namespace svetlo {

class CheckpointFile {
public:
    /// Reads and checks `path` when it exists (throws Error naming --checkpoint), and checks
    /// that it can be written.
    CheckpointFile(std::string path, const RenderJob& job);

    /// The engine's side (RenderOptions::checkpoint); it must outlive the render.
    const Checkpoint& callbacks() const { return callbacks_; }
    /// The passes the file held when it was read (0: none).
    int resumed_passes() const { return passes_; }

private:
    std::string path_, key_;
    int passes_ = 0;
    std::vector<double> state_;
    Checkpoint callbacks_;
};

}  // namespace svetlo
