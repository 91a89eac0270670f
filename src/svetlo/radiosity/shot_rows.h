// The progressive solver's rows of form factors (progressive.cpp): what a patch's shot
// sends to each leaf, made at its first shot and kept for its later ones. Internal to
// radiosity/.
#pragma once

#include <optional>
#include <vector>

#include "svetlo/core/bit_cast.h"
#include "svetlo/radiosity/hemicube.h"
#include "svetlo/radiosity/solver.h"

namespace svetlo {

/// What one side of a patch sends to the leaves: a shot of radiosity dB gives the side
/// (target[i] & 1) of leaf (target[i] >> 1) the irradiance dB * factor[i], W/m^2. Only the
/// leaves that receive something are listed.
struct ShotRow {
    std::vector<uint32_t> target;
    std::vector<float> factor;
    size_t bytes() const {
        return target.capacity() * sizeof(uint32_t) + factor.capacity() * sizeof(float);
    }
};

/// The shooters' rows, each made at its first shot and kept while the cache's memory lasts
/// (render.radiosity.form_factor_cache_mib): a patch shoots about seven times before the unshot
/// power falls to 1e-3, and a kept row makes each later shot a pass over its entries instead
/// of a form factor and `samples` rays per leaf. A row does not depend on when it is made, so
/// the solution is the same with the cache or without it.
class Shooter {
public:
    /// Rows are made for the leaves `mine` marks (this rank's share), the others left out.
    Shooter(SolverInput& in, const std::vector<uint32_t>& leaves,
            const std::vector<uint32_t>& patch_of, const std::vector<uint8_t>& mine, size_t patches)
        : in_(in),
          leaves_(leaves),
          patch_of_(patch_of),
          mine_(mine),
          dense_(leaves.size()),
          cached_(2 * patches),
          budget_(static_cast<size_t>(in.settings.form_factor_cache_mib) << 20) {
        if (in.settings.form_factors == FormFactorMethod::Hemicube) {
            const Bounds3 bounds = in.list.bounds();
            hemicube_.emplace(in.settings.hemicube, bounds);
            triangles_ = in.tree.leaf_triangles(leaves);
            hemicube_row_.assign(leaves.size(), 0.0f);
        }
    }

    /// The row of patch `patch` (node `node`) shooting from its side `side`.
    const ShotRow& row(uint32_t patch, uint32_t node, int side) {
        std::optional<ShotRow>& kept = cached_[2 * patch + side];
        if (kept) return *kept;
        ShotRow made = make_row(patch, node, side);
        if (used_ + made.bytes() > budget_) {
            scratch_ = std::move(made);
            return scratch_;
        }
        used_ += made.bytes();
        kept = std::move(made);
        return *kept;
    }

    uint64_t rays() const { return rays_; }
    size_t cache_bytes() const { return used_; }

    /// --checkpoint: the rows kept, per slot (2 patch + side), each entry one 64-bit word: its
    /// target above its factor's bits.
    std::vector<std::vector<uint64_t>> kept_rows() const {
        std::vector<std::vector<uint64_t>> out(cached_.size());
        for (size_t slot = 0; slot < cached_.size(); ++slot) {
            if (!cached_[slot]) continue;
            const ShotRow& row = *cached_[slot];
            for (size_t i = 0; i < row.target.size(); ++i)
                out[slot].push_back(uint64_t{row.target[i]} << 32 |
                                    svetlo::bit_cast<uint32_t>(row.factor[i]));
        }
        return out;
    }
    /// Keeps, of a saved row, the entries of this rank's leaves, while the cache has room.
    void adopt(size_t slot, const uint64_t* words, size_t count) {
        if (cached_[slot]) return;  // made already (the emitters'): the same values
        ShotRow row;
        size_t entries = 0;
        for (size_t i = 0; i < count; ++i) entries += mine_[(words[i] >> 32) >> 1];
        row.target.reserve(entries);
        row.factor.reserve(entries);
        for (size_t i = 0; i < count; ++i) {
            const auto target = static_cast<uint32_t>(words[i] >> 32);
            if (!mine_[target >> 1]) continue;
            row.target.push_back(target);
            row.factor.push_back(svetlo::bit_cast<float>(static_cast<uint32_t>(words[i])));
        }
        if (used_ + row.bytes() > budget_) return;
        used_ += row.bytes();
        cached_[slot] = std::move(row);
    }

private:
    ShotRow make_row(uint32_t patch, uint32_t node, int side);

    SolverInput& in_;
    const std::vector<uint32_t>& leaves_;
    const std::vector<uint32_t>& patch_of_;
    const std::vector<uint8_t>& mine_;
    std::vector<FormFactor> dense_;
    std::vector<std::optional<ShotRow>> cached_;  // per patch and side
    ShotRow scratch_;                             // the last row the cache had no room for
    size_t budget_, used_ = 0;                    // bytes
    std::optional<Hemicube> hemicube_;
    TriangleList triangles_;
    std::vector<float> hemicube_row_;
    uint64_t rays_ = 0;
};

}  // namespace svetlo
