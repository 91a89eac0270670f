// The path tracer's sampler: its Sobol points against their definition, its eight-lane draw
// against the scalar one, and the stratification that makes it worth its cost.
#include "svetlo/pt/sobol_sampler.h"

#include <gtest/gtest.h>

#include <vector>

#include "svetlo/geometry/avx2.h"

namespace svetlo {
namespace {

/// The second Sobol dimension by its definition: the direction numbers v_0 = 2^31,
/// v_(k+1) = v_k ^ (v_k >> 1), one per set bit of the index, summed by xor.
uint32_t sobol1_by_direction_numbers(uint32_t i) {
    uint32_t v = 1u << 31, x = 0;
    for (int k = 0; k < 32; ++k, v ^= v >> 1) {
        if ((i >> k) & 1u) x ^= v;
    }
    return x;
}

TEST(SobolSampler, TheSecondDimensionIsTheDirectionNumbersSum) {
    Rng rng(1, 2);
    for (uint32_t k = 0; k < 200000; ++k) {
        uint32_t i = k < 1024 ? k : rng.next_u32();
        ASSERT_EQ(sobol1_reversed(i), reverse_bits(sobol1_by_direction_numbers(i))) << i;
    }
}

/// The first `count` samples of a pixel: `pairs` pairs of dimensions each, as the path
/// tracer draws them (next_8 blocks after a next_2d, as a camera ray and its vertices).
std::vector<std::vector<vec2>> draws(uint64_t pixel, uint32_t count, bool avx2) {
    std::vector<std::vector<vec2>> out;
    for (uint32_t i = 0; i < count; ++i) {
        SobolSampler s(7, pixel, i, avx2);
        std::vector<vec2> row{s.next_2d()};
        for (int block = 0; block < 3; ++block) {
            for (vec2 u : s.next_8()) row.push_back(u);
        }
        row.push_back(s.next_2d());
        out.push_back(row);
    }
    return out;
}

TEST(SobolSampler, EightAtOnceAreFourPairsOneAfterAnotherOnEveryRoad) {
    for (uint64_t pixel : {0u, 1u, 4242u}) {
        for (uint32_t i : {0u, 1u, 5u, 1000u, 65535u}) {
            SobolSampler pairs(3, pixel, i), eights(3, pixel, i);
            (void)pairs.next_float();  // an odd dimension first: both start the pairs at 2
            (void)eights.next_float();
            for (int block = 0; block < 4; ++block) {
                std::array<vec2, 4> e = eights.next_8();
                for (int k = 0; k < 4; ++k) ASSERT_EQ(e[k], pairs.next_2d()) << block << k;
            }
        }
    }
    if (!avx2_available()) GTEST_SKIP() << "no AVX2 here: the scalar road was checked";
    EXPECT_EQ(draws(99, 64, true), draws(99, 64, false));
}

TEST(SobolSampler, SixteenSamplesStratifyEveryPairAsAZeroTwoNet) {
    // Every pair of 16 consecutive samples is a (0, 4, 2)-net: each of the 16 cells of every
    // elementary shape (1 x 16, 2 x 8, 4 x 4, 8 x 2, 16 x 1) holds exactly one point.
    for (uint64_t pixel : {3u, 777u}) {
        auto rows = draws(pixel, 16, false);
        for (size_t d = 0; d < rows[0].size(); ++d) {
            for (int a = 0; a <= 4; ++a) {
                const int nx = 1 << a, ny = 16 >> a;
                std::vector<int> cells(16, 0);
                for (const auto& row : rows) {
                    int cx = static_cast<int>(row[d].x * nx), cy = static_cast<int>(row[d].y * ny);
                    ++cells[static_cast<size_t>(cy * nx + cx)];
                }
                for (int c : cells) ASSERT_EQ(c, 1) << "pair " << d << " shape " << nx << "x" << ny;
            }
        }
    }
}

TEST(SobolSampler, PixelsAndPairsAreScrambledApart) {
    // The same sample of two pixels, and two pairs of one pixel, differ everywhere.
    auto a = draws(10, 4, false), b = draws(11, 4, false);
    for (size_t i = 0; i < a.size(); ++i) {
        for (size_t d = 0; d < a[i].size(); ++d) {
            EXPECT_NE(a[i][d], b[i][d]);
            if (d > 0) {
                EXPECT_NE(a[i][d], a[i][d - 1]);
            }
        }
    }
}

}  // namespace
}  // namespace svetlo
