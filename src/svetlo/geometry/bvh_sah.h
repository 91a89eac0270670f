// The pieces of a binned-SAH split (Wald 2007), used by the BVH build (bvh_build.cpp): a
// primitive's build reference and the bin its centroid falls in along the split axis, here;
// the bins and the binning, the partition, the ranks that sort a small span, and the sweep
// that prices every split between bins (or between sorted references), in two forms:
//   bvh_sah_reference.h  sah::reference, plain C++: the statement of each piece (read it first)
//   bvh_sah_sse.h        sah::sse, the same with SSE (and AVX2 for the binning, partition and
//                        ranks: bvh_build_avx2.cpp), the same results
// bvh_build.cpp uses the SSE form with SVETLO_SIMD, else the reference.
#pragma once

#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <climits>
#include <cstddef>
#include <cstdint>

#include "svetlo/core/math.h"

namespace svetlo::sah {

constexpr int kBins = 16;

/// A primitive during the build: its bounds and id, 32 bytes, moved from buffer to buffer as
/// the spans are split.
struct BuildRef {
    vec3 min;
    uint32_t id;
    vec3 max;
    uint32_t bin;  // where the last binning of its span put it
    vec3 centroid() const { return 0.5f * min + 0.5f * max; }  // no overflow near 3.4e38
};
static_assert(sizeof(BuildRef) == 32 && offsetof(BuildRef, max) == 16);

/// Where a reference's centroid lies along the axis of largest centroid extent, in bins
/// (fractional), and the bin that holds it. The axis is an offset into the reference, so that
/// the per-reference work has no switch on it.
struct BinPosition {
    static_assert((kBins & (kBins - 1)) == 0, "bin() masks the index");
    int axis;
    float cmin, scale;
    explicit BinPosition(const Bounds3& centroids)
        : axis(max_dimension(centroids.extent())),
          cmin(centroids.min[axis]),
          scale(static_cast<float>(kBins) * 0.99999f / centroids.extent()[axis]) {}
    float operator()(const BuildRef& r) const {
        const auto* f = reinterpret_cast<const float*>(&r);  // min at f[0..2], max at f[4..6]
        return (0.5f * f[axis] + 0.5f * f[axis + 4] - cmin) * scale;
    }
    /// The position truncated, its bin. Every centroid lies within the centroid bounds (a
    /// child's are its primitive bounds, which hold them), so a finite position lies in
    /// [0, kBins): at most the bounds' extent times a scale a little under kBins / extent,
    /// rounded. The mask keeps anything else inside the bins, the same bin for the sweep and
    /// the partition: a NaN or infinite position (infinite coordinates, or an extent so small
    /// that its scale overflows) truncates to INT_MIN, bin 0, and a centroid rounded past its
    /// bounds in denormal arithmetic may wrap to the other end; such spans split poorly, or
    /// at the median, but the tree holds every primitive (see the test
    /// Bvh.DenormalSizedTrianglesBuildAValidTree). A clamp cost four instructions of the
    /// binning's twenty (4 % of the build).
    int bin(const BuildRef& r) const { return truncate(operator()(r)) & (kBins - 1); }

    /// x truncated toward zero, or INT_MIN where it is NaN or out of range: the SSE
    /// conversion's rule (cvttss2si), which C++'s cast leaves undefined.
    static int truncate(float x) {
#if SVETLO_SIMD
        return _mm_cvttss_si32(_mm_set_ss(x));
#else
        return x >= -2147483648.0f && x < 2147483648.0f ? static_cast<int>(x) : INT_MIN;
#endif
    }
};

}  // namespace svetlo::sah
