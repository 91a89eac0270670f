// The binned SAH's pieces (geometry/bvh_sah.h) on their own.
#include "svetlo/geometry/bvh_sah.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

#include "svetlo/core/rng.h"
#include "svetlo/geometry/avx2.h"

namespace svetlo::sah {
namespace {

/// The references of a mesh-like walk (consecutive ones close together, so that runs share a
/// bin), with bounds that tie in signed zeros and a few NaN coordinates.
std::vector<BuildRef> walk_refs(int n, uint64_t seed) {
    Rng rng(seed, 3);
    std::vector<BuildRef> refs(static_cast<size_t>(n));
    vec3 p(0.0f);
    for (int k = 0; k < n; ++k) {
        p +=
            0.02f * vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
        BuildRef& r = refs[static_cast<size_t>(k)];
        r.min = p - 0.01f * rng.next_float();
        r.max = p + 0.01f * rng.next_float();
        r.id = static_cast<uint32_t>(k);
        r.bin = 0;
        if (k % 7 == 0) r.min.y = r.max.y = (k % 14 == 0) ? 0.0f : -0.0f;  // zero ties
        if (k % 97 == 5) r.max.z = std::nanf("");
    }
    return refs;
}

TEST(BvhSah, Avx2BinningGivesTheSameBinsBitForBit) {
    if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this processor";
    for (int n : {17, 40, 63, 64, 65, 1000, 4099}) {  // one set of bins below 64, two from 64
        std::vector<BuildRef> a = walk_refs(n, static_cast<uint64_t>(n));
        Bounds3 centroids;
        for (const BuildRef& r : a) centroids.extend(r.centroid());
        for (int axis = 0; axis < 3; ++axis) {
            BinPosition position(centroids);
            position.axis = axis;  // every axis, not only the largest
            position.cmin = centroids.min[axis];
            position.scale = static_cast<float>(kBins) * 0.99999f / centroids.extent()[axis];
            std::vector<BuildRef> b = a;
            Bins sse, avx;
            bin_range(a.data(), 0, static_cast<uint32_t>(n), position, sse, false);
            bin_range_avx2(b.data(), 0, static_cast<uint32_t>(n), position, avx);
            for (int k = 0; k < kBins; ++k) {
                EXPECT_EQ(sse.count[k], avx.count[k])
                    << n << " refs, axis " << axis << ", bin " << k;
                // Lanes 0-2 as bits: signed zeros and NaN must agree too.
                EXPECT_EQ(std::memcmp(&sse.min[k], &avx.min[k], 12), 0) << n << ", bin " << k;
                EXPECT_EQ(std::memcmp(&sse.max[k], &avx.max[k], 12), 0) << n << ", bin " << k;
            }
            for (int k = 0; k < n; ++k)
                ASSERT_EQ(a[static_cast<size_t>(k)].bin, b[static_cast<size_t>(k)].bin) << k;
        }
    }
}

TEST(BvhSah, Avx2PartitionMovesTheSameReferences) {
    if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this processor";
    std::vector<BuildRef> src = walk_refs(1000, 9);
    Rng rng(5, 5);
    uint32_t left = 0;
    for (BuildRef& r : src) {
        r.bin = static_cast<uint32_t>(rng.next_float() * kBins) % kBins;
        left += r.bin <= 6 ? 1u : 0u;
    }
    // Into the middle of larger buffers: nothing outside [10, 1010) may change.
    std::vector<BuildRef> sse(1020), avx(1020);
    std::memset(sse.data(), 0xab, sse.size() * sizeof(BuildRef));
    std::memset(avx.data(), 0xab, avx.size() * sizeof(BuildRef));
    partition_range(src.data(), sse.data() + 10, 0, 1000, 0, left, 6, false);
    partition_range_avx2(src.data(), avx.data() + 10, 0, 1000, 0, left, 6);
    EXPECT_EQ(std::memcmp(sse.data(), avx.data(), sse.size() * sizeof(BuildRef)), 0);
    // The SSE one as the reference: left references first, each side in order.
    uint32_t l = 0, r = left;
    for (const BuildRef& ref : src) {
        const BuildRef& moved = sse[10 + (ref.bin <= 6 ? l++ : r++)];
        ASSERT_EQ(std::memcmp(&moved, &ref, sizeof(BuildRef)), 0) << ref.id;
    }
}

TEST(BvhSah, RanksAreAStableSortOnEveryPath) {
    Rng rng(11, 4);
    for (int trial = 0; trial < 200; ++trial) {
        const auto n = 1 + static_cast<uint32_t>(trial % kBins);
        alignas(32) float key[kBins];
        for (uint32_t k = 0; k < kBins; ++k) {
            // Few distinct values, so that ties are common; infinities at either end.
            const int v = static_cast<int>(rng.next_float() * 6.0f);
            key[k] = k >= n ? kInfinity : v == 0 ? -kInfinity : v == 5 ? kInfinity : 0.5f * v;
        }
        std::vector<uint32_t> order(n);
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(),
                         [&](uint32_t a, uint32_t b) { return key[a] < key[b]; });
        uint32_t expected[kBins], sse[kBins], avx[kBins];
        for (uint32_t r = 0; r < n; ++r) expected[order[r]] = r;
        rank_keys(key, n, sse, false);
        for (uint32_t k = 0; k < n; ++k)
            ASSERT_EQ(sse[k], expected[k]) << "n " << n << ", key " << k;
        if (!avx2_available()) continue;
        rank_keys(key, n, avx, true);
        for (uint32_t k = 0; k < n; ++k)
            ASSERT_EQ(avx[k], expected[k]) << "n " << n << ", key " << k;
    }
}

}  // namespace
}  // namespace svetlo::sah
