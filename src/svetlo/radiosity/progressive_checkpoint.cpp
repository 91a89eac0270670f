#include "svetlo/radiosity/progressive_checkpoint.h"

#include <algorithm>
#include <cstring>

#include "svetlo/core/error.h"

namespace svetlo {

namespace {

/// How often a checkpointed solve saves, seconds at least: the state is the leaves' light and
/// the rows, megabytes for a large mesh, so not after every shot.
constexpr double kSaveSeconds = 1.0;

}  // namespace

size_t ProgressiveCheckpoint::fixed_size() const {
    return 1 + 12 * state_.leaves.size() + 6 * state_.patches.size();
}

ProgressiveCheckpoint::ProgressiveCheckpoint(SolverInput& in, ShootingState& state,
                                             Shooter& shooter, Shares& shares)
    : in_(in), state_(state), shooter_(shooter), shares_(shares) {
    if (!in.checkpoint) return;
    std::vector<double> saved;  // empty: whatever size the file holds
    if (in.checkpoint->restore(saved) == 0) return;
    size_t pos = 0;
    auto take = [&](Sides& s) {
        for (int side = 0; side < 2; ++side, pos += 3)
            s.v[side] = Color(static_cast<float>(saved[pos]), static_cast<float>(saved[pos + 1]),
                              static_cast<float>(saved[pos + 2]));
    };
    auto refuse = [&] {
        throw Error(in.file, "--checkpoint", "does not fit this radiosity solve");
    };
    const size_t leaves = state.leaves.size(), patches = state.patches.size();
    if (saved.size() < fixed_size() + 2 * patches) refuse();
    state.shots = static_cast<int>(saved[pos++]);
    for (size_t k = 0; k < leaves; ++k) {
        take(state.received[k]);
        take(state.direct[k]);
    }
    for (Patch& p : state.patches) take(p.unshot);
    for (size_t slot = 0; slot < 2 * patches; ++slot) {
        const double n = pos < saved.size() ? saved[pos++] : -1.0;
        if (!(n >= 0.0 && n <= static_cast<double>(saved.size() - pos))) refuse();
        const auto count = static_cast<size_t>(n);
        if (count > 0) {
            std::vector<uint64_t> words(count);
            std::memcpy(words.data(), saved.data() + pos, count * sizeof(uint64_t));
            for (uint64_t w : words)
                if ((w >> 33) >= leaves) refuse();
            shooter.adopt(slot, words.data(), count);
        }
        pos += count;
    }
    if (pos != saved.size()) refuse();
}

bool ProgressiveCheckpoint::due() const {
    if (!in_.checkpoint) return false;
    const double since = std::chrono::duration<double>(Clock::now() - saved_at_).count();
    return since >= std::max(kSaveSeconds, 10 * save_seconds_);
}

void ProgressiveCheckpoint::save() {
    const auto before = Clock::now();
    shares_.share_leaves(state_.received);
    shares_.share_leaves(state_.direct);
    std::vector<std::vector<uint64_t>> rows = shooter_.kept_rows();
    shares_.share_rows(rows);
    if (shares_.speaker()) {
        std::vector<double> out;
        out.reserve(fixed_size());
        auto add = [&](const Sides& s) {
            for (int side = 0; side < 2; ++side)
                out.insert(out.end(), {s.v[side].r, s.v[side].g, s.v[side].b});
        };
        out.push_back(state_.shots);
        for (size_t k = 0; k < state_.leaves.size(); ++k) {
            add(state_.received[k]);
            add(state_.direct[k]);
        }
        for (const Patch& p : state_.patches) add(p.unshot);
        for (const std::vector<uint64_t>& row : rows) {
            out.push_back(static_cast<double>(row.size()));
            const size_t at = out.size();
            out.resize(at + row.size());
            if (!row.empty())  // (memcpy wants pointers, even for nothing)
                std::memcpy(out.data() + at, row.data(), row.size() * sizeof(uint64_t));
        }
        in_.checkpoint->save(state_.shots, out);
    }
    saved_at_ = Clock::now();
    save_seconds_ = std::chrono::duration<double>(saved_at_ - before).count();
}

void ProgressiveCheckpoint::finish() {
    if (in_.checkpoint && state_.shots > 0) {
        save();
    } else {
        shares_.share_leaves(state_.received);
        shares_.share_leaves(state_.direct);
    }
}

}  // namespace svetlo
