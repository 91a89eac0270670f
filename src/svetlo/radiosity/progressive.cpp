// Progressive refinement: shooting from patches onto elements (solver.h).
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <optional>
#include <unordered_map>

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

/// One shooter and where its light goes.
class Shooter {
public:
    Shooter(SolverInput& in, const std::vector<uint32_t>& leaves)
        : in_(in), leaves_(leaves), delta_(leaves.size()) {
        if (in.settings.form_factors == FormFactorMethod::Hemicube) {
            Bounds3 bounds = in.list.bounds();
            hemicube_.emplace(in.settings.hemicube, bounds);
            triangles_ = in.tree.leaf_triangles(leaves);
            row_.assign(leaves.size(), 0.0f);
        }
    }

    /// The irradiance each leaf gets from `node`'s side `side` shooting radiosity dB (0 for
    /// the leaves of `skip`, the patch itself), into delta().
    void shoot(uint32_t node, int side, Color dB, uint32_t skip_patch,
               const std::vector<uint32_t>& patch_of, uint64_t step) {
        const ElementTree& tree = in_.tree;
        const ElementNode& p = tree.node(node);
        if (hemicube_) {
            std::fill(row_.begin(), row_.end(), 0.0f);
            vec3 n = side == 0 ? tree.normal(node) : -tree.normal(node);
            hemicube_->gather(triangles_, p.centroid, n, row_, in_.threads);
        }
        std::atomic<uint64_t> rays{0};
        parallel_ranges(
            leaves_.size(), in_.threads,
            [&](size_t begin, size_t end) {
                uint64_t local_rays = 0;
                for (size_t k = begin; k < end; ++k) {
                    delta_[k] = Sides{};
                    uint32_t leaf = leaves_[k];
                    const ElementNode& e = tree.node(leaf);
                    if (patch_of[k] == skip_patch) continue;
                    if (hemicube_) {
                        // Reciprocity: F_ep = A_p F_pe / A_e, onto the side facing the hemicube.
                        delta_[k].v[tree.side_facing(leaf, p.centroid)] =
                            dB * (row_[k] * p.area / e.area);
                        continue;
                    }
                    // Only the shooting side's light: the side of the patch that faces e.
                    if (tree.side_facing(node, e.centroid) != side) continue;
                    FormFactor F = form_factor(in_.ff, leaf, node, in_.seed ^ step, local_rays);
                    for (int s = 0; s < 2; ++s) delta_[k].v[s] = dB * F.F[s];
                }
                rays += local_rays;
            },
            256);
        rays_ += rays.load();
    }

    const std::vector<Sides>& delta() const { return delta_; }
    uint64_t rays() const { return rays_; }

private:
    SolverInput& in_;
    const std::vector<uint32_t>& leaves_;
    std::vector<Sides> delta_;
    std::optional<Hemicube> hemicube_;
    TriangleList triangles_;
    std::vector<float> row_;
    uint64_t rays_ = 0;
};

}  // namespace

Solution solve_progressive(SolverInput& in) {
    ElementTree& tree = in.tree;
    const std::vector<uint32_t> leaves = tree.leaves();
    Solution sol;
    sol.E.assign(tree.nodes().size(), Sides{});
    sol.direct.assign(tree.nodes().size(), Sides{});

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
    double power = 0.0;  // W (summed over the channels): emitted, and reflected from lights
    for (size_t k = 0; k < leaves.size(); ++k) {
        const ElementNode& e = tree.node(leaves[k]);
        Patch& p = patches[patch_of[k]];
        for (int s = 0; s < 2; ++s) {
            sol.E[leaves[k]].v[s] = sol.direct[leaves[k]].v[s] = light[k].v[s];
            Color reflected = e.reflectance * light[k].v[s];
            p.unshot.v[s] += reflected * (e.area / p.area);
            power += channel_sum(reflected) * e.area;
        }
        power += channel_sum(e.emission) * e.area;
    }

    Shooter shooter(in, leaves);
    uint64_t step = 0;
    auto receive = [&](bool direct) {
        const std::vector<Sides>& delta = shooter.delta();
        for (size_t k = 0; k < leaves.size(); ++k) {
            const uint32_t leaf = leaves[k];
            const ElementNode& e = tree.node(leaf);
            Patch& q = patches[patch_of[k]];
            for (int side = 0; side < 2; ++side) {
                const Color dE = delta[k].v[side];
                if (is_black(dE)) continue;
                sol.E[leaf].v[side] += dE;
                if (direct) sol.direct[leaf].v[side] += dE;
                q.unshot.v[side] += e.reflectance * dE * (e.area / q.area);
            }
        }
        ++step;
    };
    // The emitters shoot their own light first: what the elements get from it is direct.
    for (uint32_t p = 0; p < patches.size(); ++p) {
        Color emitted = tree.node(patches[p].node).emission;
        if (is_black(emitted)) continue;
        shooter.shoot(patches[p].node, 0, emitted, p, patch_of, step);
        receive(true);
    }

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
        Color dB = patches[best_patch].unshot.v[best_side];
        patches[best_patch].unshot.v[best_side] = Color(0.0f);
        shooter.shoot(patches[best_patch].node, best_side, dB, best_patch, patch_of, step);
        receive(false);
        ++sol.iterations;
    }

    // The ambient term (Cohen et al. 1988): the unshot radiosity's area mean, times the
    // interreflection factor 1 / (1 - rho_mean), as if it reached every surface evenly.
    glm::dvec3 sum_unshot(0.0), sum_rho(0.0);
    double area = 0.0;
    for (const Patch& p : patches) {
        sum_unshot += glm::dvec3(p.unshot.v[0] + p.unshot.v[1]) * static_cast<double>(p.area);
        area += p.area;
    }
    for (uint32_t leaf : leaves)
        sum_rho +=
            glm::dvec3(tree.node(leaf).reflectance) * static_cast<double>(tree.node(leaf).area);
    if (area > 0.0 && in.settings.ambient_term) {
        glm::dvec3 rho = glm::min(sum_rho / area, glm::dvec3(0.999));
        sol.ambient = Color(sum_unshot / area / (glm::dvec3(1.0) - rho));
    }
    sol.rays = shooter.rays();
    return sol;
}

}  // namespace svetlo
