// --checkpoint FILE (docs/distributed.md): a render's state and how far it holds (the path
// tracer's sums after each pass, the radiosity solve's light and rows after some shots, or under
// mpirun the path tracer's tiles done), saved atomically (a temporary file, then a rename),
// with the key of the run they belong to: a hash of the effective scene and the settings that
// change its pixels. The same command with the same FILE resumes where the last save left,
// and its image is bit for bit an uninterrupted run's. A file of another run, or one that is
// corrupt or truncated, is refused with one line before the render starts.
#pragma once

#include <string>
#include <vector>

#include "svetlo/job/render_job.h"

namespace svetlo {

class CheckpointFile {
public:
    /// Whose state the file holds: the engine's (its passes' sums, the radiosity solve), or,
    /// under mpirun, the ray tracers' tiles done (distributed.h). Each has its own key, so one
    /// is never read as the other.
    enum class Layout { Engine, Tiles };

    /// Reads and checks `path` when it exists (throws Error naming --checkpoint), and checks
    /// that it can be written. Only a `writer` saves (under mpirun, rank 0).
    CheckpointFile(std::string path, const RenderJob& job, Layout layout = Layout::Engine,
                   bool writer = true);

    /// The engine's side (RenderOptions::checkpoint); it must outlive the render.
    const Checkpoint& callbacks() const { return callbacks_; }
    /// The passes the file held when it was read (0: none).
    int resumed_passes() const { return passes_; }
    /// What the file held when it was read (Layout::Tiles: its owner lays it out).
    const std::vector<double>& saved() const { return state_; }
    void save(int passes, const std::vector<double>& state) const {
        callbacks_.save(passes, state);
    }

private:
    std::string path_, key_;
    int passes_ = 0;
    std::vector<double> state_;
    Checkpoint callbacks_;
};

}  // namespace svetlo
