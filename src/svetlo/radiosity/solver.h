// Radiosity's solvers (docs/radiosity.md): they all solve, per side of every element i,
//
//   B_i = E_i^e + rho_i (L_i + sum_j F_ij B_j)     W/m^2,
//
// the lecture's equation with E^e = pi L_e the emitted radiosity (front sides only) and L_i
// the irradiance that point, spot and directional lights and the background give straight
// (light_shooting.h), shot onto the elements before the solve. What they return is each
// element's irradiance, whole and straight from the emitters, from which display.h draws.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "svetlo/core/process_group.h"
#include "svetlo/core/progress.h"
#include "svetlo/geometry/accel.h"
#include "svetlo/radiosity/element_tree.h"
#include "svetlo/radiosity/form_factors.h"
#include "svetlo/scene/renderer.h"

namespace svetlo {

/// A value per side of a node: [0] in front, [1] behind.
struct Sides {
    Color v[2] = {Color(0.0f), Color(0.0f)};
};

struct Solution;

struct SolverInput {
    ElementTree& tree;
    const Accel& accel;        // the scene's triangles, for visibility
    const TriangleList& list;  // the same triangles (the hemicube draws the leaves)
    const RadiositySettings& settings;
    FormFactorContext ff;
    /// The irradiance lights and the background give node id straight, per side (L above).
    std::function<Sides(uint32_t id)> light_at;
    uint64_t seed = 0;
    int threads = 0;
    Progress* progress = nullptr;  // its status shows the iteration, residual and unshot light
    std::string file;              // the scene's, for the errors the solvers raise
    /// When set, the progressive solver shows it the solution as it stands after 0, 1, 2, 4
    /// ... shots (the ambient term included): the error against time of compare --curves.
    std::function<void(const Solution& partial)> on_snapshot;
    /// The progressive solver only (docs/distributed.md): the ranks that split the solve among
    /// them (null: this process alone), the --checkpoint it resumes from and saves to, and the
    /// flag that stops it after the shot in progress (SIGINT, SIGTERM).
    ProcessGroup* group = nullptr;
    const Checkpoint* checkpoint = nullptr;
    const std::atomic<bool>* cancel = nullptr;
};

struct Solution {
    std::vector<Sides> E;       // per node (leaves meaningful): irradiance received, W/m^2
    std::vector<Sides> direct;  // per node: the part straight from lights and emitters
    Color ambient{0.0f};        // progressive: the unshot light's ambient irradiance
    int iterations = 0;         // sweeps, shots, or hierarchical gathers
    double residual = 0.0;      // power still unshot or changing, over the power emitted
    uint64_t rays = 0;
    uint64_t links = 0;      // hierarchical: links made
    size_t patches = 0;      // progressive: the shooters
    size_t cache_bytes = 0;  // progressive: the form-factor rows kept (form_factor_cache_mib)
};

/// The number of elements at most the matrix solvers (Jacobi, Gauss-Seidel) take: their
/// matrix holds n^2 form factors.
inline constexpr size_t kMaxMatrixElements = 4096;

/// Progressive refinement (Cohen, Chen, Wallace and Greenberg 1988): the patch with the most
/// unshot power shoots it to every element (Southwell's iteration), until the unshot power
/// falls below the tolerance; O(n) memory, and each shooter's row of form factors kept for its
/// later shots within settings.form_factor_cache_mib. The emitters shoot their own light
/// first, which is the solution's direct part.
Solution solve_progressive(SolverInput& in);
/// Jacobi or Gauss-Seidel sweeps on the full matrix of element-to-element form factors.
Solution solve_matrix(SolverInput& in, bool gauss_seidel);
/// Hierarchical radiosity (hierarchical.cpp): links between nodes at the level the oracle
/// allows, making at most `max_nodes` nodes in all.
Solution solve_hierarchical(SolverInput& in, size_t max_nodes);

/// Shows "WHAT N, LEFT_WHAT R% of the power" on the progress bar, if there is one.
inline void report_progress(Progress* progress, const char* what, int iteration,
                            const char* residual_name, double residual) {
    if (!progress) return;
    char status[112];
    std::snprintf(status, sizeof status, "%s %d, %s %.3g%% of the power", what, iteration,
                  residual_name, 100.0 * residual);
    progress->set_status(status);
    progress->advance(0);
}

/// The luminance-like sum of a colour's channels (power comparisons).
inline float channel_sum(Color c) { return c.r + c.g + c.b; }

}  // namespace svetlo
