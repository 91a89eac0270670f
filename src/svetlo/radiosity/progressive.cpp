// Progressive refinement: shooting from patches onto elements (solver.h).
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <optional>
#include <unordered_map>
#include <utility>

#include "svetlo/core/parallel.h"
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
    Shooter(SolverInput& in, const std::vector<uint32_t>& leaves,
            const std::vector<uint32_t>& patch_of, size_t patches)
        : in_(in),
          leaves_(leaves),
          patch_of_(patch_of),
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
    std::vector<FormFactor> dense_;
    std::vector<std::optional<ShotRow>> cached_;  // per patch and side
    ShotRow scratch_;                             // the last row the cache had no room for
    size_t budget_, used_ = 0;                    // bytes
    std::optional<Hemicube> hemicube_;
    TriangleList triangles_;
    std::vector<float> hemicube_row_;
    uint64_t rays_ = 0;
};

}  // namespace

Solution solve_progressive(SolverInput& in) {
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

    // The lights' direct irradiance on every leaf, reflected into its patch's unshot light.
    std::vector<Sides> light(leaves.size());
    parallel_ranges(
        leaves.size(), in.threads,
        [&](size_t begin, size_t end) {
            for (size_t k = begin; k < end; ++k) light[k] = in.light_at(leaves[k]);
        },
        64);
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
    Shooter shooter(in, leaves, patch_of, patches.size());
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
    double unshot = 0.0;
    while (power > 0.0) {
        // Southwell: the patch and side with the most unshot power.
        unshot = 0.0;
        double best = -1.0;
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
        // Snapshots after 0, 1, 2, 4, 8 ... shots (compare --curves, --mse-log).
        if (in.on_snapshot && (sol.iterations & (sol.iterations - 1)) == 0) {
            fill_solution(sol);
            in.on_snapshot(sol);
        }
        Color dB = patches[best_patch].unshot.v[best_side];
        patches[best_patch].unshot.v[best_side] = Color(0.0f);
        shoot(best_patch, best_side, dB, false);
        ++sol.iterations;
    }
    fill_solution(sol);
    sol.rays = shooter.rays();
    sol.cache_bytes = shooter.cache_bytes();
    sol.patches = patches.size();
    return sol;
}

}  // namespace svetlo
