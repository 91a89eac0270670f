// The fast path's kernel built for AVX2 (eight lanes); simd_shading.cpp calls it when the
// processor has AVX2. This file alone is compiled with -mavx2.
#include <immintrin.h>

#include "svetlo/raster/simd_shading.h"

namespace svetlo {

#define SVETLO_SIMD_WIDTH 8
#include "svetlo/raster/simd_kernel.inc"

void shade_run_avx2(const TriangleRun& q, float dl1, float dl2, int first, int groups,
                    const SimdMaterial& mat, vec3 ng, const SimdLights& lights, vec3 eye,
                    bool ortho, vec3 forward, Color ambient, Color* out) {
    shade_run_kernel(q, dl1, dl2, first, groups, mat, ng, lights, eye, ortho, forward, ambient,
                     out);
}

}  // namespace svetlo
