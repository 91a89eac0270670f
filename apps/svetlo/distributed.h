// One image on many processes (docs/distributed.md: `mpirun -np N build/svetlo render ...`;
// docs/distributed.md). Every rank reads the scene and sets up its engine once (the BVH, the
// radiosity solve); rank 0 hands out the film's tiles one at a time, to the ranks that ask
// and to itself between its own tiles, so a slow rank takes fewer; each tile is a window of
// the engine (WindowSource), bit for bit the full render's pixels; rank 0 gathers them and
// alone writes the image. The image is the one process's whatever N, the ranks' speeds or
// the threads. Built with OpenMPI where CMake finds it; without it there is one process.
#pragma once

#include <cstdint>

#include "svetlo/job/checkpoint.h"
#include "svetlo/job/render_job.h"

namespace svetlo {

/// The MPI job the program runs in: MPI is started only when the program was launched by
/// mpirun (or another launcher that says so in the environment), and finished at the end.
class MpiSession {
public:
    MpiSession(int& argc, char**& argv);
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    /// Ends every process of the job after an error on this one (no rank is left waiting).
    [[noreturn]] void abort(int status) const;

private:
    int rank_ = 0, size_ = 1;
    bool started_ = false;
};

/// What a distributed render moved and how its tiles were shared.
struct DistributedStats {
    int tiles = 0;
    uint64_t bytes = 0;      // sent to rank 0, every rank's tiles together
    int rank0_tiles = 0;     // rendered by rank 0 itself
    int resumed_tiles = 0;   // held by the checkpoint it resumed from
    uint64_t exchanged = 0;  // received by all ranks together in the setup's exchanges (the
                             // radiosity solve's)
};

/// Renders the job on every rank of `mpi` (one rank: run_job). Rank 0 returns the full image
/// and its AOVs; the other ranks return an empty result. `stats` is filled on rank 0.
/// `checkpoint` (Layout::Tiles, the ray tracers): rank 0 resumes from the tiles it holds and
/// saves the tiles done as they come in, at most once a second and at the end.
RenderResult run_job_distributed(const RenderJob& job, const MpiSession& mpi,
                                 DistributedStats& stats, const CheckpointFile* checkpoint);

}  // namespace svetlo
