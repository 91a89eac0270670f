// The binned SAH's pieces (geometry/bvh_sah.h) on their own: the plain twins
// (bvh_sah_reference.h) against what they state, and the SSE and AVX2 forms against the twins.
#include "svetlo/geometry/bvh_sah.h"

#include "svetlo/geometry/bvh_sah_reference.h"
#if SVETLO_SIMD
#include "svetlo/geometry/bvh_sah_sse.h"
#endif

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
std::vector<BuildRef> walk_refs(int n, uint64_t seed, bool with_nan = true) {
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
        if (with_nan && k % 97 == 5) r.max.z = std::nanf("");
    }
    return refs;
}

/// A position along `axis` for refs' centroids.
BinPosition position_along(const std::vector<BuildRef>& refs, int axis) {
    Bounds3 centroids;
    for (const BuildRef& r : refs) centroids.extend(r.centroid());
    BinPosition position(centroids);
    position.axis = axis;  // every axis, not only the largest
    position.cmin = centroids.min[axis];
    position.scale = static_cast<float>(kBins) * 0.99999f / centroids.extent()[axis];
    return position;
}

TEST(BvhSah, ReferenceBinsHoldTheirReferences) {
    std::vector<BuildRef> refs = walk_refs(1000, 3, false);
    const BinPosition position = position_along(refs, 0);
    reference::Bins bins;
    reference::bin_range(refs.data(), 0, 1000, position, bins);
    uint32_t total = 0;
    for (int b = 0; b < kBins; ++b) total += bins.count[b];
    EXPECT_EQ(total, 1000u);
    for (const BuildRef& r : refs) {
        ASSERT_EQ(static_cast<int>(r.bin), position.bin(r));
        const int b = static_cast<int>(r.bin);
        for (int a = 0; a < 3; ++a) {
            ASSERT_LE(bins.min[b][a], r.min[a]);
            ASSERT_GE(bins.max[b][a], r.max[a]);
        }
    }
}

#if SVETLO_SIMD
TEST(BvhSah, SseAndAvx2BinningGiveTheReferenceBins) {
    for (int n : {17, 40, 63, 64, 65, 1000, 4099}) {  // one set of bins below 64, two from 64
        // NaN-free: the forms meet the references in different orders, and a bin keeps or
        // drops a NaN by the order (bvh_sah_reference.h).
        std::vector<BuildRef> a = walk_refs(n, static_cast<uint64_t>(n), false);
        for (int axis = 0; axis < 3; ++axis) {
            const BinPosition position = position_along(a, axis);
            std::vector<BuildRef> b = a;
            reference::Bins plain;
            sse::Bins fast;
            reference::bin_range(b.data(), 0, static_cast<uint32_t>(n), position, plain);
            sse::bin_range(a.data(), 0, static_cast<uint32_t>(n), position, fast, false);
            for (int k = 0; k < kBins; ++k) {
                EXPECT_EQ(plain.count[k], fast.count[k]) << n << " refs, axis " << axis;
                const Bounds3 box = sse::to_bounds(fast.min[k], fast.max[k]);
                if (plain.count[k] == 0) continue;
                EXPECT_EQ(plain.min[k], box.min) << n << ", bin " << k;  // as numbers
                EXPECT_EQ(plain.max[k], box.max) << n << ", bin " << k;
            }
            for (int k = 0; k < n; ++k)
                ASSERT_EQ(a[static_cast<size_t>(k)].bin, b[static_cast<size_t>(k)].bin) << k;
        }
    }
}

TEST(BvhSah, Avx2BinningGivesTheSameBinsBitForBit) {
    if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this processor";
    for (int n : {17, 40, 63, 64, 65, 1000, 4099}) {  // one set of bins below 64, two from 64
        std::vector<BuildRef> a = walk_refs(n, static_cast<uint64_t>(n));
        for (int axis = 0; axis < 3; ++axis) {
            const BinPosition position = position_along(a, axis);
            std::vector<BuildRef> b = a;
            sse::Bins sse, avx;
            sse::bin_range(a.data(), 0, static_cast<uint32_t>(n), position, sse, false);
            sse::bin_range_avx2(b.data(), 0, static_cast<uint32_t>(n), position, avx);
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

TEST(BvhSah, SseSweepChoosesTheReferenceSplit) {
    Rng rng(21, 2);
    for (int trial = 0; trial < 300; ++trial) {
        const int cells = 2 + trial % (kBins - 1);
        std::vector<BuildRef> refs = walk_refs(cells, static_cast<uint64_t>(trial) + 100, false);
        for (BuildRef& r : refs)
            if (rng.next_float() < 0.1f) r.max = r.min;  // flat boxes: zero areas, ties
        const reference::Sweep plain(cells, static_cast<uint32_t>(cells),
                                     [&](int b) { return reference::cell_of(refs[b]); });
        const sse::Sweep fast(cells, static_cast<uint32_t>(cells),
                              [&](int b) { return sse::cell_of(refs[b]); });
        float plain_cost = kInfinity, fast_cost = kInfinity;
        const int a = plain.cheapest(plain_cost), b = fast.cheapest(fast_cost);
        ASSERT_EQ(a, b) << "trial " << trial;
        ASSERT_EQ(std::memcmp(&plain_cost, &fast_cost, 4), 0) << "trial " << trial;
        if (a < 0) continue;
        const Bounds3 box = sse::to_bounds(fast.left_min[a], fast.left_max[a]);
        EXPECT_EQ(plain.left_min[a], box.min);
        EXPECT_EQ(plain.left_max[a], box.max);
        EXPECT_EQ(plain.left_count[a], fast.left_count[a]);
    }
}
#endif

TEST(BvhSah, PartitionMovesTheSameReferencesOnEveryPath) {
    std::vector<BuildRef> src = walk_refs(1000, 9);
    Rng rng(5, 5);
    uint32_t left = 0;
    for (BuildRef& r : src) {
        r.bin = static_cast<uint32_t>(rng.next_float() * kBins) % kBins;
        left += r.bin <= 6 ? 1u : 0u;
    }
    // Into the middle of larger buffers: nothing outside [10, 1010) may change.
    std::vector<BuildRef> plain(1020);
    std::memset(plain.data(), 0xab, plain.size() * sizeof(BuildRef));
    std::vector<BuildRef> untouched = plain;
    reference::partition_range(src.data(), plain.data() + 10, 0, 1000, 0, left, 6);
    // Left references first, each side in order; nothing outside [10, 1010) written.
    uint32_t l = 0, r = left;
    for (const BuildRef& ref : src) {
        const BuildRef& moved = plain[10 + (ref.bin <= 6 ? l++ : r++)];
        ASSERT_EQ(std::memcmp(&moved, &ref, sizeof(BuildRef)), 0) << ref.id;
    }
    EXPECT_EQ(std::memcmp(plain.data(), untouched.data(), 10 * sizeof(BuildRef)), 0);
    EXPECT_EQ(std::memcmp(&plain[1010], &untouched[1010], 10 * sizeof(BuildRef)), 0);
#if SVETLO_SIMD
    for (bool avx2 : {false, true}) {
        if (avx2 && !avx2_available()) continue;
        std::vector<BuildRef> fast = untouched;
        sse::partition_range(src.data(), fast.data() + 10, 0, 1000, 0, left, 6, avx2);
        EXPECT_EQ(std::memcmp(plain.data(), fast.data(), plain.size() * sizeof(BuildRef)), 0)
            << (avx2 ? "AVX2" : "SSE");
    }
#endif
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
        uint32_t expected[kBins], rank[kBins];
        for (uint32_t r = 0; r < n; ++r) expected[order[r]] = r;
        reference::rank_keys(key, n, rank);
        for (uint32_t k = 0; k < n; ++k)
            ASSERT_EQ(rank[k], expected[k]) << "reference, n " << n << ", key " << k;
#if SVETLO_SIMD
        for (bool avx2 : {false, true}) {
            if (avx2 && !avx2_available()) continue;
            sse::rank_keys(key, n, rank, avx2);
            for (uint32_t k = 0; k < n; ++k)
                ASSERT_EQ(rank[k], expected[k]) << (avx2 ? "AVX2" : "SSE") << ", n " << n;
        }
#endif
    }
}

}  // namespace
}  // namespace svetlo::sah
