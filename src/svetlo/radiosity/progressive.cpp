// Progressive refinement (solver.h): Southwell's iteration, shooting from patches onto
// elements. The lesson is solve_progressive's loop; the rows it keeps (shot_rows.h), the
// ranks' shares of a distributed solve (progressive_shares.h) and --checkpoint
// (progressive_checkpoint.h) reach it through small interfaces of their own, each doing
// nothing on one process without a checkpoint.
#include <unordered_map>

#include "svetlo/core/parallel.h"
#include "svetlo/radiosity/progressive_checkpoint.h"
#include "svetlo/radiosity/progressive_shares.h"
#include "svetlo/radiosity/progressive_state.h"
#include "svetlo/radiosity/shot_rows.h"

namespace svetlo {

namespace {

/// The patches: each leaf's ancestor at its root's patch level.
ShootingState patches_of(const ElementTree& tree, float patch_size) {
    ShootingState st;
    st.leaves = tree.leaves();
    st.patch_of.resize(st.leaves.size());
    std::unordered_map<uint32_t, uint32_t> patch_index;
    for (size_t k = 0; k < st.leaves.size(); ++k) {
        const uint32_t root = tree.node(st.leaves[k]).root;
        uint32_t node = tree.ancestor_at(st.leaves[k], tree.level_for(root, patch_size));
        auto [it, made] = patch_index.try_emplace(node, static_cast<uint32_t>(st.patches.size()));
        if (made) st.patches.push_back(Patch{node, tree.node(node).area, Sides{}});
        st.patch_of[k] = it->second;
    }
    return st;
}

/// The lights' direct irradiance on every leaf (each rank its own, then shared), reflected
/// into its patch's unshot light; and the power in the scene.
void receive_lights(const SolverInput& in, ShootingState& st, Shares& shares) {
    const ElementTree& tree = in.tree;
    const size_t n = st.leaves.size();
    std::vector<Sides> light(n);
    parallel_ranges(
        n, in.threads,
        [&](size_t begin, size_t end) {
            for (size_t k = begin; k < end; ++k)
                if (shares.mine()[k]) light[k] = in.light_at(st.leaves[k]);
        },
        64);
    shares.share_leaves(light);
    st.received.resize(n);
    st.direct.resize(n);
    st.to_unshot.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const ElementNode& e = tree.node(st.leaves[k]);
        Patch& p = st.patches[st.patch_of[k]];
        st.to_unshot[k] = e.reflectance * (e.area / p.area);
        st.received[k] = st.direct[k] = light[k];
        for (int s = 0; s < 2; ++s) {
            p.unshot.v[s] += st.to_unshot[k] * light[k].v[s];
            st.power += channel_sum(e.reflectance * light[k].v[s]) * e.area;
        }
        st.power += channel_sum(e.emission) * e.area;
    }
}

/// Patch `p` shoots radiosity dB (W/m^2) from its side `side`: every leaf its row reaches
/// receives dB times its form factor, and its patch's unshot light grows by what it reflects.
/// (Only this rank's leaves, and so only its own patches' unshot light.)
void shoot(ShootingState& st, Shooter& rows, uint32_t p, int side, Color dB, bool is_direct) {
    const ShotRow& row = rows.row(p, st.patches[p].node, side);
    for (size_t i = 0; i < row.target.size(); ++i) {
        const uint32_t k = row.target[i] >> 1, s = row.target[i] & 1;
        const Color dE = dB * row.factor[i];
        st.received[k].v[s] += dE;
        if (is_direct) st.direct[k].v[s] += dE;
        st.patches[st.patch_of[k]].unshot.v[s] += st.to_unshot[k] * dE;
    }
}

/// Southwell's choice: the patch and side with the most unshot power (W, summed over the
/// channels), and the unshot power in all.
struct Brightest {
    uint32_t patch = 0;
    int side = 0;
    double unshot = 0.0;
};
Brightest brightest(const std::vector<Patch>& patches) {
    Brightest b;
    double best = -1.0;
    for (uint32_t p = 0; p < patches.size(); ++p) {
        for (int s = 0; s < 2; ++s) {
            const double w =
                static_cast<double>(channel_sum(patches[p].unshot.v[s])) * patches[p].area;
            b.unshot += w;
            if (w > best) {
                best = w;
                b.patch = p;
                b.side = s;
            }
        }
    }
    return b;
}

/// The solution as it stands: what each leaf has received, and the ambient term (Cohen et
/// al. 1988): the unshot radiosity's area mean, times the interreflection factor
/// 1 / (1 - rho_mean), as if it reached every surface evenly.
void fill_solution(const SolverInput& in, const ShootingState& st, Solution& out) {
    const ElementTree& tree = in.tree;
    out.E.assign(tree.nodes().size(), Sides{});
    out.direct.assign(tree.nodes().size(), Sides{});
    for (size_t k = 0; k < st.leaves.size(); ++k) {
        out.E[st.leaves[k]] = st.received[k];
        out.direct[st.leaves[k]] = st.direct[k];
    }
    glm::dvec3 sum_unshot(0.0), sum_rho(0.0);
    double area = 0.0;
    for (const Patch& p : st.patches) {
        sum_unshot += glm::dvec3(p.unshot.v[0] + p.unshot.v[1]) * static_cast<double>(p.area);
        area += p.area;
    }
    for (uint32_t leaf : st.leaves)
        sum_rho +=
            glm::dvec3(tree.node(leaf).reflectance) * static_cast<double>(tree.node(leaf).area);
    out.ambient = Color(0.0f);
    if (area > 0.0 && in.settings.ambient_term) {
        glm::dvec3 rho = glm::min(sum_rho / area, glm::dvec3(0.999));
        out.ambient = Color(sum_unshot / area / (glm::dvec3(1.0) - rho));
    }
}

}  // namespace

Solution solve_progressive(SolverInput& in) {
    ShootingState st = patches_of(in.tree, in.settings.patch_size);
    Shares shares(in.group, st.patch_of, st.patches.size());
    Shooter rows(in, st.leaves, st.patch_of, shares.mine(), st.patches.size());
    receive_lights(in, st, shares);
    // The emitters shoot their own light first: what the elements get from it is direct.
    for (uint32_t p = 0; p < st.patches.size(); ++p) {
        const Color emitted = in.tree.node(st.patches[p].node).emission;
        if (!is_black(emitted)) shoot(st, rows, p, 0, emitted, true);
    }
    ProgressiveCheckpoint checkpoint(in, st, rows, shares);  // resumes a saved solve

    Solution sol;
    const int max_shots =
        in.settings.max_iterations > 0
            ? in.settings.max_iterations
            : static_cast<int>(std::min<size_t>(100 * st.patches.size() + 1000, 100000000));
    while (st.power > 0.0) {
        // Rank 0 decides for all whether to stop (a signal) or save; the ranks then agree on
        // every patch's unshot light.
        const int order = shares.agree(st.patches, (in.cancel && in.cancel->load() ? kStop : 0) |
                                                       (checkpoint.due() ? kSave : 0));
        const Brightest b = brightest(st.patches);
        sol.iterations = st.shots;
        sol.residual = b.unshot / st.power;
        report_progress(in.progress, "shot", st.shots, "unshot", sol.residual);
        if (sol.residual < in.settings.tolerance || st.shots >= max_shots) break;
        if (order & kStop) break;  // the image of the shots done (the ambient term shows the rest)
        if ((order & kSave) && st.shots > 0) checkpoint.save();
        // Snapshots after 0, 1, 2, 4, 8 ... shots (compare --curves, --mse-log; one process).
        if (in.on_snapshot && (st.shots & (st.shots - 1)) == 0) {
            fill_solution(in, st, sol);
            in.on_snapshot(sol);
        }
        const Color dB = st.patches[b.patch].unshot.v[b.side];
        st.patches[b.patch].unshot.v[b.side] = Color(0.0f);
        shoot(st, rows, b.patch, b.side, dB, false);
        ++st.shots;
    }
    checkpoint.finish();
    fill_solution(in, st, sol);
    sol.iterations = st.shots;
    sol.rays = shares.sum(rows.rays());
    sol.cache_bytes = static_cast<size_t>(shares.sum(rows.cache_bytes()));
    sol.patches = st.patches.size();
    return sol;
}

}  // namespace svetlo
