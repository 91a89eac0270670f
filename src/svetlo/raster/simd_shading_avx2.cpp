// The fast path's kernel built for AVX2 (eight lanes); simd_shading.cpp calls it only where
// the processor has AVX2. The target is set by pragma around the kernel alone, not by a flag
// for the whole file: inline functions of the headers (GLM, the standard library) are thus
// never emitted with AVX2 instructions that the linker could pick for the rest of the program.
#include <immintrin.h>

#include <algorithm>

#include "svetlo/raster/simd_shading.h"

#pragma GCC push_options
#pragma GCC target("avx2")

namespace svetlo {

#define SVETLO_SIMD_WIDTH 8
#include "svetlo/raster/simd_kernel.inc"

void shade_batch_avx2(const ShadeBatch& b, const SimdLights& lights, vec3 eye, bool ortho,
                      vec3 forward, Color ambient, const LightVisibility& vis, Color* out) {
    shade_batch_kernel(b, 0, lights, eye, ortho, forward, ambient, vis, out);
}

void shade_run_avx2(const TriangleRun& q, float dl1, float dl2, int first, int groups,
                    const SimdMaterial& mat, vec3 ng, const SimdLights& lights, vec3 eye,
                    bool ortho, vec3 forward, Color ambient, const LightVisibility& vis,
                    Color* out) {
    shade_run_kernel(q, dl1, dl2, first, groups, mat, ng, lights, eye, ortho, forward, ambient, vis,
                     out);
}

}  // namespace svetlo

#pragma GCC pop_options
