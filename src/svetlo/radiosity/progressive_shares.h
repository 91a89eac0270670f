// The ranks' shares of a distributed progressive solve (docs/distributed.md, "Radiosity on
// many ranks"): who owns which patches and leaves, and the exchanges after each shot. On one
// process every exchange does nothing. Internal to radiosity/.
#pragma once

#include <algorithm>
#include <cstring>
#include <vector>

#include "svetlo/core/process_group.h"
#include "svetlo/radiosity/progressive_state.h"

namespace svetlo {

/// The ranks' shares of the solve (docs/distributed.md, "Radiosity on many ranks"): the patches
/// are dealt out to the ranks, about the same number of leaves each and neighbouring patches to
/// different ranks (so that each shot's work is shared: a shooter lights its neighbours less),
/// and each rank owns its patches' leaves. It makes its leaves' part of every row, keeps their
/// light, and updates its patches' unshot light; after each shot the ranks exchange the patches'
/// unshot light, so that every rank picks the same shooter. A patch's leaves are all one rank's, so
/// each patch's sums are added up in the order one process adds them: the solution is bit for bit
/// the same on any number of ranks. Alone (no group, or a group of one), nothing is exchanged.
class Shares {
public:
    Shares(ProcessGroup* group, const std::vector<uint32_t>& patch_of, size_t patches)
        : group_(group && group->size() > 1 ? group : nullptr), patch_of_(patch_of) {
        const int ranks = group_ ? group_->size() : 1;
        const int me = group_ ? group_->rank() : 0;
        std::vector<size_t> weight(patches, 0);
        for (uint32_t p : patch_of) ++weight[p];
        owner_ = deal_by_weight(weight, ranks);
        patch_floats_.assign(static_cast<size_t>(ranks), 0);
        for (int r : owner_) patch_floats_[static_cast<size_t>(r)] += kFloats;
        patch_floats_[0] += 1;  // rank 0's control word
        mine_.resize(patch_of.size());
        leaf_floats_.assign(static_cast<size_t>(ranks), 0);
        for (size_t k = 0; k < patch_of.size(); ++k) {
            const int r = owner_[patch_of[k]];
            mine_[k] = r == me;
            leaf_floats_[static_cast<size_t>(r)] += kFloats;
        }
    }

    /// Per leaf: whether it is this rank's.
    const std::vector<uint8_t>& mine() const { return mine_; }
    bool speaker() const { return !group_ || group_->rank() == 0; }

    /// Gives every rank each leaf's value from the leaf's owner.
    void share_leaves(std::vector<Sides>& values) {
        if (!group_) return;
        std::vector<float> out;
        out.reserve(leaf_floats_[static_cast<size_t>(group_->rank())]);
        for (size_t k = 0; k < values.size(); ++k)
            if (mine_[k]) put(out, values[k]);
        const std::vector<float> all = gather(out, leaf_floats_);
        std::vector<size_t> at = starts(leaf_floats_);  // where each rank's next value is
        for (size_t k = 0; k < values.size(); ++k) {
            size_t& pos = at[static_cast<size_t>(owner_[patch_of_[k]])];
            values[k] = take(all, pos);
        }
    }

    /// Gives every rank each patch's unshot light from its owner, and returns rank 0's
    /// `control` (a Control mask) on every rank.
    int agree(std::vector<Patch>& patches, int control) {
        if (!group_) return control;
        const int me = group_->rank();
        std::vector<float> out;
        for (size_t p = 0; p < patches.size(); ++p)
            if (owner_[p] == me) put(out, patches[p].unshot);
        if (me == 0) out.push_back(static_cast<float>(control));
        const std::vector<float> all = gather(out, patch_floats_);
        std::vector<size_t> at = starts(patch_floats_);
        for (size_t p = 0; p < patches.size(); ++p)
            patches[p].unshot = take(all, at[static_cast<size_t>(owner_[p])]);
        return static_cast<int>(all[at[0]]);
    }

    /// Gives every rank the whole of each row, from the parts the ranks made (Shooter::
    /// kept_rows): each row's entries in target order, as one process makes them.
    void share_rows(std::vector<std::vector<uint64_t>>& rows) {
        if (!group_) return;
        std::vector<uint64_t> out;  // per row its length, then its entries
        for (const std::vector<uint64_t>& row : rows) {
            out.push_back(row.size());
            out.insert(out.end(), row.begin(), row.end());
        }
        const size_t ranks = patch_floats_.size();
        const std::vector<uint64_t> sizes =
            gather(std::vector<uint64_t>{out.size()}, std::vector<size_t>(ranks, 1));
        const std::vector<uint64_t> all =
            gather(out, std::vector<size_t>(sizes.begin(), sizes.end()));
        for (std::vector<uint64_t>& row : rows) row.clear();
        for (size_t pos = 0; pos < all.size();) {  // rank after rank
            for (std::vector<uint64_t>& row : rows) {
                const size_t n = all[pos++];
                row.insert(row.end(), all.begin() + static_cast<std::ptrdiff_t>(pos),
                           all.begin() + static_cast<std::ptrdiff_t>(pos + n));
                pos += n;
            }
        }
        for (std::vector<uint64_t>& row : rows) std::sort(row.begin(), row.end());
    }

    /// The sum of a count over the ranks.
    uint64_t sum(uint64_t value) { return group_ ? group_->sum(value) : value; }

private:
    static constexpr int kFloats = 6;  // a Sides
    static void put(std::vector<float>& out, const Sides& s) {
        out.insert(out.end(), {s.v[0].r, s.v[0].g, s.v[0].b, s.v[1].r, s.v[1].g, s.v[1].b});
    }
    static Sides take(const std::vector<float>& in, size_t& pos) {
        Sides s;
        s.v[0] = Color(in[pos], in[pos + 1], in[pos + 2]);
        s.v[1] = Color(in[pos + 3], in[pos + 4], in[pos + 5]);
        pos += kFloats;
        return s;
    }
    static std::vector<size_t> starts(const std::vector<size_t>& counts) {
        std::vector<size_t> at(counts.size(), 0);
        for (size_t r = 1; r < counts.size(); ++r) at[r] = at[r - 1] + counts[r - 1];
        return at;
    }
    /// all_gather of values of a plain type, `counts` in values.
    template <class T>
    std::vector<T> gather(const std::vector<T>& mine, const std::vector<size_t>& counts) {
        std::vector<std::byte> in(mine.size() * sizeof(T)), all;
        if (!in.empty()) std::memcpy(in.data(), mine.data(), in.size());
        std::vector<size_t> bytes(counts.size());
        for (size_t r = 0; r < counts.size(); ++r) bytes[r] = counts[r] * sizeof(T);
        group_->all_gather(in, bytes, all);
        std::vector<T> out(all.size() / sizeof(T));
        if (!out.empty()) std::memcpy(out.data(), all.data(), out.size() * sizeof(T));
        return out;
    }

    ProcessGroup* group_;
    const std::vector<uint32_t>& patch_of_;
    std::vector<int> owner_;            // per patch
    std::vector<uint8_t> mine_;         // per leaf
    std::vector<size_t> leaf_floats_;   // per rank: its leaves' floats in share_leaves
    std::vector<size_t> patch_floats_;  // per rank: its patches' floats in share_patches
};

/// What the ranks' leader tells them before each shot (Shares::agree).
enum Control : int { kGoOn = 0, kStop = 1, kSave = 2 };

}  // namespace svetlo
