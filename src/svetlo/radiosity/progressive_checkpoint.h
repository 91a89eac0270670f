// --checkpoint for the progressive solve (docs/distributed.md): the shots done, per leaf what
// it received (whole and direct), per patch its unshot light, then the rows kept: per slot
// (2 patch + side) its length and its entries (Shooter::kept_rows, each word's bits held in a
// double). With the rows, a resumed solve does not make them again: making them is most of a
// solve's time. Internal to radiosity/.
#pragma once

#include <chrono>

#include "svetlo/radiosity/progressive_shares.h"
#include "svetlo/radiosity/progressive_state.h"
#include "svetlo/radiosity/shot_rows.h"

namespace svetlo {

class ProgressiveCheckpoint {
public:
    /// Restores the solve that `in.checkpoint` holds, if any, into `state` and `shooter`;
    /// throws Error naming --checkpoint when it does not fit. Without --checkpoint, nothing.
    ProgressiveCheckpoint(SolverInput& in, ShootingState& state, Shooter& shooter, Shares& shares);

    /// Whether a save is due: a second has passed since the last (and ten times its time, so
    /// that at most a tenth of the time goes to saving). Never without --checkpoint.
    bool due() const;
    /// Saves: rank 0 writes, every rank gathers the leaves' light and the rows for it.
    void save();
    /// As the solve ends: a save (a rerun shows it again at once) where there is a checkpoint
    /// and a shot was done, else only the leaves' light gathered on every rank.
    void finish();

private:
    using Clock = std::chrono::steady_clock;
    size_t fixed_size() const;

    SolverInput& in_;
    ShootingState& state_;
    Shooter& shooter_;
    Shares& shares_;
    Clock::time_point saved_at_ = Clock::now();
    double save_seconds_ = 0.0;  // the last save's
};

}  // namespace svetlo
