// Progressive refinement: shooting from patches onto elements (solver.h).
#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <unordered_map>
#include <utility>

#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/process_group.h"
#include "svetlo/radiosity/hemicube.h"
#include "svetlo/radiosity/solver.h"

namespace svetlo {

namespace {

struct Patch {
    uint32_t node;
    float area;
    Sides unshot;  // radiosity not yet shot, W/m^2
};

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
                                    std::bit_cast<uint32_t>(row.factor[i]));
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
            row.factor.push_back(std::bit_cast<float>(static_cast<uint32_t>(words[i])));
        }
        if (used_ + row.bytes() > budget_) return;
        used_ += row.bytes();
        cached_[slot] = std::move(row);
    }

private:
    ShotRow make_row(uint32_t patch, uint32_t node, int side) {
        const ElementTree& tree = in_.tree;
        const ElementNode& p = tree.node(node);
        if (hemicube_) {
            std::fill(hemicube_row_.begin(), hemicube_row_.end(), 0.0f);
            vec3 n = side == 0 ? tree.normal(node) : -tree.normal(node);
            hemicube_->gather(triangles_, p.centroid, n, hemicube_row_, in_.threads);
        }
        std::atomic<uint64_t> rays{0};
        parallel_ranges(
            leaves_.size(), in_.threads,
            [&](size_t begin, size_t end) {
                uint64_t local_rays = 0;
                for (size_t k = begin; k < end; ++k) {
                    dense_[k] = FormFactor{};
                    const uint32_t leaf = leaves_[k];
                    const ElementNode& e = tree.node(leaf);
                    if (!mine_[k]) continue;              // another rank's
                    if (patch_of_[k] == patch) continue;  // a patch does not light itself
                    if (hemicube_) {
                        // Reciprocity: F_ep = A_p F_pe / A_e, onto the side facing the hemicube.
                        dense_[k].F[tree.side_facing(leaf, p.centroid)] =
                            hemicube_row_[k] * p.area / e.area;
                        continue;
                    }
                    // Only the shooting side's light: the side of the patch that faces e.
                    if (tree.side_facing(node, e.centroid) != side) continue;
                    dense_[k] = form_factor(in_.ff, leaf, node, in_.seed, local_rays);
                }
                rays += local_rays;
            },
            256);
        rays_ += rays.load();
        // Exactly the room the entries take: the cache's budget counts it.
        size_t entries = 0;
        for (const FormFactor& F : dense_) entries += (F.F[0] > 0.0f) + (F.F[1] > 0.0f);
        ShotRow out;
        out.target.reserve(entries);
        out.factor.reserve(entries);
        for (size_t k = 0; k < leaves_.size(); ++k) {
            for (int s = 0; s < 2; ++s) {
                if (!(dense_[k].F[s] > 0.0f)) continue;
                out.target.push_back(static_cast<uint32_t>(2 * k + s));
                out.factor.push_back(dense_[k].F[s]);
            }
        }
        return out;
    }

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

    /// Gives every rank each patch's unshot light from its owner, and rank 0's `control`.
    void share_patches(std::vector<Patch>& patches, float& control) {
        if (!group_) return;
        const int me = group_->rank();
        std::vector<float> out;
        for (size_t p = 0; p < patches.size(); ++p)
            if (owner_[p] == me) put(out, patches[p].unshot);
        if (me == 0) out.push_back(control);
        const std::vector<float> all = gather(out, patch_floats_);
        std::vector<size_t> at = starts(patch_floats_);
        for (size_t p = 0; p < patches.size(); ++p)
            patches[p].unshot = take(all, at[static_cast<size_t>(owner_[p])]);
        control = all[at[0]];
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

/// What the ranks' leader tells them before each shot (Shares::share_patches).
enum Control : int { kGoOn = 0, kStop = 1, kSave = 2 };

/// How often a checkpointed solve saves (--checkpoint), seconds at least: the state is the
/// leaves' light and the rows, megabytes for a large mesh, so not after every shot (and never
/// sooner than ten times the last save's time after it: at most a tenth of the time saving).
constexpr double kSaveSeconds = 1.0;

}  // namespace

Solution solve_progressive(SolverInput& in) {
    using Clock = std::chrono::steady_clock;
    ElementTree& tree = in.tree;
    const std::vector<uint32_t> leaves = tree.leaves();
    Solution sol;

    // The patches: each leaf's ancestor at its root's patch level.
    std::vector<Patch> patches;
    std::vector<uint32_t> patch_of(leaves.size());
    std::unordered_map<uint32_t, uint32_t> patch_index;
    for (size_t k = 0; k < leaves.size(); ++k) {
        const uint32_t root = tree.node(leaves[k]).root;
        uint32_t node = tree.ancestor_at(leaves[k], tree.level_for(root, in.settings.patch_size));
        auto [it, made] = patch_index.try_emplace(node, static_cast<uint32_t>(patches.size()));
        if (made) patches.push_back(Patch{node, tree.node(node).area, Sides{}});
        patch_of[k] = it->second;
    }
    Shares shares(in.group, patch_of, patches.size());
    const std::vector<uint8_t>& mine = shares.mine();

    // The lights' direct irradiance on every leaf (each rank its own, then shared), reflected
    // into its patch's unshot light.
    std::vector<Sides> light(leaves.size());
    parallel_ranges(
        leaves.size(), in.threads,
        [&](size_t begin, size_t end) {
            for (size_t k = begin; k < end; ++k)
                if (mine[k]) light[k] = in.light_at(leaves[k]);
        },
        64);
    shares.share_leaves(light);
    // Per leaf k: the irradiance it has received, and what a watt per square metre of it adds
    // to its patch's unshot radiosity (its reflectance times its share of the patch's area).
    std::vector<Sides> received(leaves.size()), direct(leaves.size());
    std::vector<Color> to_unshot(leaves.size());
    double power = 0.0;  // W (summed over the channels): emitted, and reflected from lights
    for (size_t k = 0; k < leaves.size(); ++k) {
        const ElementNode& e = tree.node(leaves[k]);
        Patch& p = patches[patch_of[k]];
        to_unshot[k] = e.reflectance * (e.area / p.area);
        received[k] = direct[k] = light[k];
        for (int s = 0; s < 2; ++s) {
            p.unshot.v[s] += to_unshot[k] * light[k].v[s];
            power += channel_sum(e.reflectance * light[k].v[s]) * e.area;
        }
        power += channel_sum(e.emission) * e.area;
    }
    Shooter shooter(in, leaves, patch_of, mine, patches.size());
    // A shot reaches this rank's leaves, and so only its own patches' unshot light.
    auto shoot = [&](uint32_t p, int side, Color dB, bool is_direct) {
        const ShotRow& row = shooter.row(p, patches[p].node, side);
        for (size_t i = 0; i < row.target.size(); ++i) {
            const uint32_t k = row.target[i] >> 1, s = row.target[i] & 1;
            const Color dE = dB * row.factor[i];
            received[k].v[s] += dE;
            if (is_direct) direct[k].v[s] += dE;
            patches[patch_of[k]].unshot.v[s] += to_unshot[k] * dE;
        }
    };
    // The emitters shoot their own light first: what the elements get from it is direct.
    for (uint32_t p = 0; p < patches.size(); ++p) {
        Color emitted = tree.node(patches[p].node).emission;
        if (!is_black(emitted)) shoot(p, 0, emitted, true);
    }

    // --checkpoint: the shots done, per leaf what it received (whole and direct), per patch its
    // unshot light, then the rows kept: per slot (2 patch + side) its length and its entries
    // (Shooter::kept_rows, each word's bits held in a double). With the rows, a resumed solve
    // does not make them again: making them is most of a solve's time.
    const size_t fixed = 1 + 12 * leaves.size() + 6 * patches.size();
    if (in.checkpoint) {
        std::vector<double> saved;  // empty: whatever size the file holds
        if (in.checkpoint->restore(saved) > 0) {
            size_t pos = 0;
            auto take = [&](Sides& s) {
                for (int side = 0; side < 2; ++side, pos += 3)
                    s.v[side] =
                        Color(static_cast<float>(saved[pos]), static_cast<float>(saved[pos + 1]),
                              static_cast<float>(saved[pos + 2]));
            };
            auto refuse = [&] {
                throw Error(in.file, "--checkpoint", "does not fit this radiosity solve");
            };
            if (saved.size() < fixed + 2 * patches.size()) refuse();
            sol.iterations = static_cast<int>(saved[pos++]);
            for (size_t k = 0; k < leaves.size(); ++k) {
                take(received[k]);
                take(direct[k]);
            }
            for (Patch& p : patches) take(p.unshot);
            for (size_t slot = 0; slot < 2 * patches.size(); ++slot) {
                const double n = pos < saved.size() ? saved[pos++] : -1.0;
                if (!(n >= 0.0 && n <= static_cast<double>(saved.size() - pos))) refuse();
                const auto count = static_cast<size_t>(n);
                if (count > 0) {
                    std::vector<uint64_t> words(count);
                    std::memcpy(words.data(), saved.data() + pos, count * sizeof(uint64_t));
                    for (uint64_t w : words)
                        if ((w >> 33) >= leaves.size()) refuse();
                    shooter.adopt(slot, words.data(), count);
                }
                pos += count;
            }
            if (pos != saved.size()) refuse();
        }
    }
    // Saves (rank 0 writes; every rank gathers the leaves' light and the rows for it).
    auto save = [&] {
        shares.share_leaves(received);
        shares.share_leaves(direct);
        std::vector<std::vector<uint64_t>> rows = shooter.kept_rows();
        shares.share_rows(rows);
        if (!shares.speaker()) return;
        std::vector<double> out;
        out.reserve(fixed);
        auto add = [&](const Sides& s) {
            for (int side = 0; side < 2; ++side)
                out.insert(out.end(), {s.v[side].r, s.v[side].g, s.v[side].b});
        };
        out.push_back(sol.iterations);
        for (size_t k = 0; k < leaves.size(); ++k) {
            add(received[k]);
            add(direct[k]);
        }
        for (const Patch& p : patches) add(p.unshot);
        for (const std::vector<uint64_t>& row : rows) {
            out.push_back(static_cast<double>(row.size()));
            const size_t at = out.size();
            out.resize(at + row.size());
            if (!row.empty())  // (memcpy wants pointers, even for nothing)
                std::memcpy(out.data() + at, row.data(), row.size() * sizeof(uint64_t));
        }
        in.checkpoint->save(sol.iterations, out);
    };

    // The solution as it stands: what each leaf has received, and the ambient term
    // (Cohen et al. 1988): the unshot radiosity's area mean, times the interreflection factor
    // 1 / (1 - rho_mean), as if it reached every surface evenly.
    auto fill_solution = [&](Solution& out) {
        out.E.assign(tree.nodes().size(), Sides{});
        out.direct.assign(tree.nodes().size(), Sides{});
        for (size_t k = 0; k < leaves.size(); ++k) {
            out.E[leaves[k]] = received[k];
            out.direct[leaves[k]] = direct[k];
        }
        glm::dvec3 sum_unshot(0.0), sum_rho(0.0);
        double area = 0.0;
        for (const Patch& p : patches) {
            sum_unshot += glm::dvec3(p.unshot.v[0] + p.unshot.v[1]) * static_cast<double>(p.area);
            area += p.area;
        }
        for (uint32_t leaf : leaves)
            sum_rho +=
                glm::dvec3(tree.node(leaf).reflectance) * static_cast<double>(tree.node(leaf).area);
        out.ambient = Color(0.0f);
        if (area > 0.0 && in.settings.ambient_term) {
            glm::dvec3 rho = glm::min(sum_rho / area, glm::dvec3(0.999));
            out.ambient = Color(sum_unshot / area / (glm::dvec3(1.0) - rho));
        }
    };

    const int max_shots =
        in.settings.max_iterations > 0
            ? in.settings.max_iterations
            : static_cast<int>(std::min<size_t>(100 * patches.size() + 1000, 100000000));
    auto saved_at = Clock::now();
    double save_seconds = 0.0;  // the last save's: saves are spaced ten times as far
    while (power > 0.0) {
        // Rank 0 decides for all whether to stop (a signal) or save (a second has passed).
        float control = kGoOn;
        if (shares.speaker()) {
            const bool stop = in.cancel && in.cancel->load();
            const double since = std::chrono::duration<double>(Clock::now() - saved_at).count();
            const bool due = in.checkpoint && since >= std::max(kSaveSeconds, 10 * save_seconds);
            control = static_cast<float>((stop ? kStop : 0) | (due ? kSave : 0));
        }
        shares.share_patches(patches, control);
        const int order = static_cast<int>(control);
        // Southwell: the patch and side with the most unshot power.
        double unshot = 0.0, best = -1.0;
        uint32_t best_patch = 0;
        int best_side = 0;
        for (uint32_t p = 0; p < patches.size(); ++p) {
            for (int s = 0; s < 2; ++s) {
                double w =
                    static_cast<double>(channel_sum(patches[p].unshot.v[s])) * patches[p].area;
                unshot += w;
                if (w > best) {
                    best = w;
                    best_patch = p;
                    best_side = s;
                }
            }
        }
        sol.residual = unshot / power;
        report_progress(in.progress, "shot", sol.iterations, "unshot", sol.residual);
        if (sol.residual < in.settings.tolerance || sol.iterations >= max_shots) break;
        if (order & kStop) break;  // the image of the shots done (the ambient term shows the rest)
        if ((order & kSave) && sol.iterations > 0) {
            const auto before = Clock::now();
            save();
            saved_at = Clock::now();
            save_seconds = std::chrono::duration<double>(saved_at - before).count();
        }
        // Snapshots after 0, 1, 2, 4, 8 ... shots (compare --curves, --mse-log; one process).
        if (in.on_snapshot && (sol.iterations & (sol.iterations - 1)) == 0) {
            fill_solution(sol);
            in.on_snapshot(sol);
        }
        Color dB = patches[best_patch].unshot.v[best_side];
        patches[best_patch].unshot.v[best_side] = Color(0.0f);
        shoot(best_patch, best_side, dB, false);
        ++sol.iterations;
    }
    if (in.checkpoint && sol.iterations > 0) {
        save();  // the solve as it ends: a rerun shows it again at once
    } else {
        shares.share_leaves(received);
        shares.share_leaves(direct);
    }
    fill_solution(sol);
    sol.rays = shares.sum(shooter.rays());
    sol.cache_bytes = static_cast<size_t>(shares.sum(shooter.cache_bytes()));
    sol.patches = patches.size();
    return sol;
}

}  // namespace svetlo
