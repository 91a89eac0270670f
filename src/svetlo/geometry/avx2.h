// Whether the geometry library's AVX2 code may run: it is compiled (GCC on x86-64, in files
// of their own under a target pragma) and the processor has AVX2 (checked once, at run
// time). The eight-wide BVH's traversal uses it, and the BVH build's binning, partition and
// small spans' ranks; so do the rasterizer's AVX2 files (its shading kernel, a depth-only
// pass's setup), compiled under the same conditions.
#pragma once

namespace svetlo {

bool avx2_available();

/// Whether the sixteen-wide BVH's AVX-512 traversal (wide_bvh_avx512.cpp) is compiled and the
/// processor has AVX-512 F (checked once, at run time).
bool avx512_available();

}  // namespace svetlo
