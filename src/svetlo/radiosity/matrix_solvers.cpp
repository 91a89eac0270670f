// Jacobi and Gauss-Seidel on the full matrix of element-to-element form factors (solver.h):
// the lecture's linear system, for small scenes.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <memory>

#include "svetlo/core/parallel.h"
#include "svetlo/radiosity/hemicube.h"
#include "svetlo/radiosity/solver.h"

namespace svetlo {

namespace {

/// The matrix of the leaves' form factors: F[i n + j] from element i (its side facing j) to
/// element j, and side[i n + j] that side; by rays between the elements or by hemicubes.
struct FormFactorMatrix {
    std::vector<float> F;
    std::vector<uint8_t> side;
    uint64_t rays = 0;
};

FormFactorMatrix form_factor_matrix(SolverInput& in, const std::vector<uint32_t>& leaves) {
    ElementTree& tree = in.tree;
    const size_t n = leaves.size();
    FormFactorMatrix m;
    m.F.assign(n * n, 0.0f);
    m.side.assign(n * n, 0);
    std::vector<float>& F = m.F;
    std::vector<uint8_t>& side = m.side;
    std::atomic<uint64_t> rays{0};
    const bool hemicube = in.settings.form_factors == FormFactorMethod::Hemicube;
    TriangleList triangles;
    if (hemicube) triangles = tree.leaf_triangles(leaves);
    const Bounds3 bounds = in.list.bounds();
    parallel_ranges(
        n, in.threads,
        [&](size_t begin, size_t end) {
            uint64_t local_rays = 0;
            std::unique_ptr<Hemicube> cube;
            std::vector<float> row;
            if (hemicube) {
                cube = std::make_unique<Hemicube>(in.settings.hemicube, bounds);
                row.resize(n);
            }
            for (size_t i = begin; i < end; ++i) {
                const ElementNode& e = tree.node(leaves[i]);
                for (size_t j = 0; j < n; ++j)
                    side[i * n + j] = static_cast<uint8_t>(
                        tree.side_facing(leaves[i], tree.node(leaves[j]).centroid));
                if (!hemicube) {
                    for (size_t j = 0; j < n; ++j) {
                        if (j == i) continue;
                        // Both sides' form factors on the side that faces j's centroid: the
                        // matrix keeps one per pair (docs/radiosity.md).
                        F[i * n + j] =
                            form_factor(in.ff, leaves[i], leaves[j], in.seed, local_rays).sum();
                    }
                    continue;
                }
                for (int s = 0; s < 2; ++s) {
                    std::fill(row.begin(), row.end(), 0.0f);
                    vec3 normal = s == 0 ? tree.normal(leaves[i]) : -tree.normal(leaves[i]);
                    cube->gather(triangles, e.centroid, normal, row, 1);
                    for (size_t j = 0; j < n; ++j)
                        if (j != i && side[i * n + j] == s) F[i * n + j] += row[j];
                }
            }
            rays += local_rays;
        },
        4);
    m.rays = rays.load();
    return m;
}

/// The light each leaf receives from the lights (`light`, L) and from the emitters directly
/// (sol.direct); B starts at E^e + rho L. Returns B's power (W, over both sides).
double start_solution(SolverInput& in, const std::vector<uint32_t>& leaves,
                      const FormFactorMatrix& m, std::vector<Sides>& light, std::vector<Sides>& B,
                      Solution& sol) {
    const ElementTree& tree = in.tree;
    const size_t n = leaves.size();
    const std::vector<float>& F = m.F;
    const std::vector<uint8_t>& side = m.side;
    parallel_ranges(
        n, in.threads,
        [&](size_t begin, size_t end) {
            for (size_t k = begin; k < end; ++k) light[k] = in.light_at(leaves[k]);
        },
        64);
    double power = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const ElementNode& e = tree.node(leaves[i]);
        for (int s = 0; s < 2; ++s) {
            B[i].v[s] = (s == 0 ? e.emission : Color(0.0f)) + e.reflectance * light[i].v[s];
            power += channel_sum(B[i].v[s]) * e.area;
        }
    }
    for (size_t i = 0; i < n; ++i) {
        Sides direct = light[i];
        for (size_t j = 0; j < n; ++j) {
            // j's front faces i when i lies on j's side 0.
            if (F[i * n + j] > 0.0f && side[j * n + i] == 0)
                direct.v[side[i * n + j]] += F[i * n + j] * tree.node(leaves[j]).emission;
        }
        sol.direct[leaves[i]] = direct;
    }
    return power;
}

}  // namespace

Solution solve_matrix(SolverInput& in, bool gauss_seidel) {
    ElementTree& tree = in.tree;
    const std::vector<uint32_t> leaves = tree.leaves();
    const size_t n = leaves.size();
    Solution sol;
    sol.E.assign(tree.nodes().size(), Sides{});
    sol.direct.assign(tree.nodes().size(), Sides{});

    const FormFactorMatrix m = form_factor_matrix(in, leaves);
    const std::vector<float>& F = m.F;
    const std::vector<uint8_t>& side = m.side;
    sol.rays = m.rays;

    // Lights first (L), then the emitters' direct light; B starts at E^e + rho L.
    std::vector<Sides> light(n), B(n);
    const double power = start_solution(in, leaves, m, light, B, sol);

    // The gather of one element from the current B: irradiance per side.
    auto gather = [&](size_t i) {
        Sides E = light[i];
        const float* row = &F[i * n];
        const uint8_t* sides = &side[i * n];
        for (size_t j = 0; j < n; ++j) {
            if (row[j] == 0.0f) continue;
            E.v[sides[j]] += row[j] * B[j].v[side[j * n + i]];
        }
        return E;
    };
    const int max_sweeps = in.settings.max_iterations > 0 ? in.settings.max_iterations : 10000;
    std::vector<Sides> next(n);
    while (power > 0.0 && sol.iterations < max_sweeps) {
        double change = 0.0;
        auto update = [&](size_t i, Sides& out) {
            const ElementNode& e = tree.node(leaves[i]);
            Sides E = gather(i);
            sol.E[leaves[i]] = E;
            for (int s = 0; s < 2; ++s)
                out.v[s] = (s == 0 ? e.emission : Color(0.0f)) + e.reflectance * E.v[s];
        };
        if (gauss_seidel) {
            // In place: each element sees the values already updated in this sweep.
            for (size_t i = 0; i < n; ++i) {
                Sides old = B[i];
                update(i, B[i]);
                for (int s = 0; s < 2; ++s)
                    change +=
                        channel_sum(glm::abs(B[i].v[s] - old.v[s])) * tree.node(leaves[i]).area;
            }
        } else {
            parallel_ranges(
                n, in.threads,
                [&](size_t begin, size_t end) {
                    for (size_t i = begin; i < end; ++i) update(i, next[i]);
                },
                64);
            for (size_t i = 0; i < n; ++i) {
                for (int s = 0; s < 2; ++s)
                    change +=
                        channel_sum(glm::abs(next[i].v[s] - B[i].v[s])) * tree.node(leaves[i]).area;
            }
            B.swap(next);
        }
        ++sol.iterations;
        sol.residual = change / power;
        report_progress(in.progress, "sweep", sol.iterations, "change", sol.residual);
        if (sol.residual < in.settings.tolerance) break;
    }
    // E from the final B (the last sweep's gather used the B before it).
    for (size_t i = 0; i < n; ++i) sol.E[leaves[i]] = gather(i);
    return sol;
}

}  // namespace svetlo
