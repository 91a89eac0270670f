// The directional quadtree of path guiding (direction_tree.h): its map of the sphere, its
// draws against its density, and its refinement.
#include "svetlo/pt/direction_tree.h"

#include <gtest/gtest.h>

#include <cmath>

#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

/// A recorder refined over a few rounds toward directions near +x and a little light from
/// everywhere, as training shapes one, and its tree.
DirectionTree lumpy_tree() {
    DirectionRecorder recorder;
    DirectionTree tree;
    Rng rng(7, 11);
    for (int round = 0; round < 4; ++round) {
        for (int k = 0; k < 20000; ++k) {
            const vec2 x(rng.next_float(), rng.next_float());
            const vec3 d = square_to_direction(x);
            const double lobe = std::pow(std::max(0.0f, d.x), 20.0f);
            recorder.add(x, static_cast<uint64_t>(1000.0 * lobe + 1.0));
        }
        tree = recorder.to_tree(1.0);
        recorder = DirectionRecorder::refined(tree, 0.01f, 20);
    }
    return tree;
}

TEST(DirectionTree, TheSquareMapsTheSphereBothWaysAndKeepsArea) {
    Rng rng(3, 5);
    for (int k = 0; k < 1000; ++k) {
        const vec2 x(rng.next_float(), rng.next_float());
        const vec3 d = square_to_direction(x);
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
        const vec2 back = direction_to_square(d);
        EXPECT_NEAR(back.x, x.x, 2e-5f);
        // phi wraps at 0 = 1.
        EXPECT_NEAR(std::remainder(back.y - x.y, 1.0f), 0.0f, 2e-5f);
    }
    // Area kept: the band 0.25 <= x < 0.5 is cos theta in [-0.5, 0), a quarter of the
    // sphere (Archimedes' hat box), as a quarter of the square.
    int inside = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        const vec2 u(rng.next_float(), rng.next_float());
        const float z = 1.0f - 2.0f * u.x;  // a uniform direction's z
        const float x = direction_to_square(vec3(0.0f, 0.0f, z) + vec3(1e-7f, 0.0f, 0.0f)).x;
        inside += x >= 0.25f && x < 0.5f;
    }
    EXPECT_NEAR(static_cast<double>(inside) / n, 0.25, 0.005);
}

TEST(DirectionTree, AnEmptyRecorderGivesNoEnergyAndOneUniformNode) {
    DirectionRecorder r;
    const DirectionTree t = r.to_tree(1.0);
    EXPECT_EQ(t.total(), 0.0f);
    EXPECT_EQ(t.pdf(vec2(0.3f, 0.6f)), 0.0f);
    EXPECT_EQ(DirectionRecorder::refined(t, 0.01f, 20).size(), 1u);
}

TEST(DirectionTree, TheDensityIsTheEnergyTimesTheCosine) {
    // One node, energies 1, 2, 3, 4 in its quadrants (each integrated over its quadrant, a
    // quarter of the square): the irradiance is (E_1 + E_3) times the cosine's mean on the
    // upper half, 1/2; the density is 4 E_q (2 x - 1) over its integral, (E_1 + E_3) / 2,
    // on the upper half, and zero below.
    DirectionTree::Node root;
    root.energy = {1.0f, 2.0f, 3.0f, 4.0f};
    const DirectionTree tree({root});
    EXPECT_FLOAT_EQ(tree.total(), 10.0f);
    EXPECT_FLOAT_EQ(tree.irradiance(), 3.0f);
    EXPECT_FLOAT_EQ(tree.pdf(vec2(0.75f, 0.25f)), 4.0f * 2.0f * 0.5f / 3.0f);
    EXPECT_FLOAT_EQ(tree.pdf(vec2(0.9f, 0.6f)), 4.0f * 4.0f * 0.8f / 3.0f);
    EXPECT_EQ(tree.pdf(vec2(0.25f, 0.75f)), 0.0f);
    EXPECT_EQ(tree.pdf(vec2(0.5f, 0.75f)), 0.0f);  // the horizon itself
    // Draws land on the upper half only, a third of them in quadrant 1 (2 of 2 + 4), and
    // their x has the cosine's mean there, E[x] = 1/2 + (1/2) E[t], E[t] = 2/3.
    Rng rng(5, 9);
    const int n = 100000;
    int lower = 0, first = 0;
    double x_sum = 0.0;
    for (int k = 0; k < n; ++k) {
        float pdf = 0.0f;
        const vec2 x = tree.sample(vec2(rng.next_float(), rng.next_float()), pdf);
        lower += x.x < 0.5f;
        first += x.y < 0.5f;
        x_sum += x.x;
    }
    EXPECT_EQ(lower, 0);
    EXPECT_NEAR(static_cast<double>(first) / n, 1.0 / 3.0, 0.006);  // 4 sigma
    EXPECT_NEAR(x_sum / n, 0.5 + 0.5 * 2.0 / 3.0, 0.002);           // sigma 0.0004
}

TEST(DirectionTree, TheDensityIntegratesToOne) {
    const DirectionTree tree = lumpy_tree();
    ASSERT_GT(tree.depth(), 4);
    // The midpoint rule on a grid finer than the deepest leaf is exact for a piecewise
    // constant density whose cells are unions of grid cells.
    const int n = 1 << std::min(tree.depth() + 1, 11);
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) sum += tree.pdf(vec2((i + 0.5f) / n, (j + 0.5f) / n));
    EXPECT_NEAR(sum / (double(n) * n), 1.0, 1e-4);
}

TEST(DirectionTree, DrawsFollowTheDensity) {
    // Chi-square of 32 x 32 cells: each cell's expected count is the density integrated over
    // it (the midpoint rule on a 4x finer grid, exact as above when the leaves are coarser,
    // and close when not), 200k draws.
    const DirectionTree tree = lumpy_tree();
    const int cells = 32, fine = 4, draws = 200000;
    std::vector<double> expected(cells * cells, 0.0), seen(cells * cells, 0.0);
    const int n = cells * fine;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const float p = tree.pdf(vec2((i + 0.5f) / n, (j + 0.5f) / n));
            expected[(j / fine) * cells + i / fine] += p / (double(n) * n) * draws;
        }
    }
    Rng rng(1, 2);
    for (int k = 0; k < draws; ++k) {
        float pdf = 0.0f;
        const vec2 x = tree.sample(vec2(rng.next_float(), rng.next_float()), pdf);
        ASSERT_TRUE(x.x >= 0.0f && x.x < 1.0f && x.y >= 0.0f && x.y < 1.0f);
        ASSERT_GT(tree.pdf(x), 0.0f);                        // never where the density is zero
        ASSERT_NEAR(pdf, tree.pdf(x), 1e-5f * tree.pdf(x));  // the draw's own density
        seen[static_cast<int>(x.y * cells) * cells + static_cast<int>(x.x * cells)] += 1.0;
    }
    double chi2 = 0.0;
    int dof = -1;
    for (size_t c = 0; c < expected.size(); ++c) {
        if (expected[c] < 5.0) continue;
        chi2 += (seen[c] - expected[c]) * (seen[c] - expected[c]) / expected[c];
        ++dof;
    }
    // The 1e-4 quantile above the mean of chi-square with dof degrees: mean + 4.5 sqrt(2 dof).
    EXPECT_LT(chi2, dof + 4.5 * std::sqrt(2.0 * dof)) << dof << " degrees of freedom";
}

TEST(DirectionTree, RefiningSplitsWhereTheEnergyIsAndAddsUpTheSameLayout) {
    DirectionRecorder r;
    // All the energy in one small spot: the spot's quadrants split to the depth where they
    // hold less than 1 % each, nothing else does.
    for (int k = 0; k < 100; ++k) r.add(vec2(0.1f, 0.1f), 100);
    r.add(vec2(0.9f, 0.9f), 1);
    const DirectionTree coarse = r.to_tree(1.0);
    EXPECT_EQ(coarse.nodes().size(), 1u);
    DirectionRecorder fine = DirectionRecorder::refined(coarse, 0.01f, 20);
    // The quadrant of (0.1, 0.1) holds 10000 of 10001: split, and so are its quarters (2500
    // each, inherited evenly) and theirs (625, then 156), but not the next (39, under 100):
    // the root and 1 + 4 + 16 + 64 nodes.
    EXPECT_EQ(fine.size(), 1u + 1u + 4u + 16u + 64u);
    for (int k = 0; k < 100; ++k) fine.add(vec2(0.1f, 0.1f), 100);
    fine.add(vec2(0.9f, 0.9f), 1);
    EXPECT_EQ(fine.total(), 10001u);
    const DirectionTree t = fine.to_tree(1.0);
    // Only leaves are added to; a quadrant with children holds its leaves' sum, the spot's
    // 10000 down every level to it.
    EXPECT_EQ(t.nodes()[0].energy, (std::array<float, 4>{10000.0f, 0.0f, 0.0f, 1.0f}));
    const uint32_t spot = t.nodes()[0].child[0];
    ASSERT_NE(spot, 0u);
    EXPECT_EQ(t.nodes()[spot].energy, (std::array<float, 4>{10000.0f, 0.0f, 0.0f, 0.0f}));
    // Nearly all the energy lies below the horizon (x < 1/2), where the cosine is zero: the
    // density is the lone record's, 4 (its quadrant's share of the square, all of the
    // irradiance) times the cosine 2 x - 1 = 0.8 over its mean there, 1/2.
    EXPECT_EQ(t.pdf(vec2(0.1f, 0.1f)), 0.0f);
    EXPECT_NEAR(t.pdf(vec2(0.9f, 0.9f)), 4.0f * 0.8f / 0.5f, 1e-5f);
    // The same energies whatever the order they were added in: integers.
    DirectionRecorder reverse = DirectionRecorder::refined(coarse, 0.01f, 20);
    reverse.add(vec2(0.9f, 0.9f), 1);
    for (int k = 0; k < 100; ++k) reverse.add(vec2(0.1f, 0.1f), 100);
    const DirectionTree u = reverse.to_tree(1.0);
    for (size_t k = 0; k < t.nodes().size(); ++k)
        EXPECT_EQ(t.nodes()[k].energy, u.nodes()[k].energy);
}

}  // namespace
}  // namespace svetlo
