// The fast path's kernel with SSE (simd_kernel.inc), and AVX2 where the processor has it. Its
// twin is the general shading (fragment.cpp, shading/bsdf.cpp): a build without SIMD keeps
// only SimdMaterial here, which the frame prepares either way.
#include "svetlo/raster/simd_shading.h"

#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>

#include "svetlo/geometry/avx2.h"
#include "svetlo/shading/bsdf.h"

namespace svetlo {

#if SVETLO_SIMD
#define SVETLO_SIMD_WIDTH 4
#include "svetlo/raster/simd_kernel.inc"

// The AVX2 build of the kernel (simd_shading_avx2.cpp), when the compiler made one.
#ifdef SVETLO_HAS_AVX2_KERNEL
void shade_batch_avx2(const ShadeBatch& b, const SimdLights& lights, vec3 eye, bool ortho,
                      vec3 forward, Color ambient, const LightVisibility& vis, Color* out);
void shade_run_avx2(const TriangleRun& q, float dl1, float dl2, int first, int groups,
                    const SimdMaterial& mat, vec3 ng, const SimdLights& lights, vec3 eye,
                    bool ortho, vec3 forward, Color ambient, const LightVisibility& vis,
                    Color* out);
#endif

namespace {

/// Whether the AVX2 kernel was built and the processor runs it (avx2.h's check, kept here:
/// asked once per batch of samples).
bool cpu_has_avx2() {
#ifdef SVETLO_HAS_AVX2_KERNEL
    static const bool has = avx2_available();
    return has;
#else
    return false;
#endif
}

}  // namespace
#endif

namespace {

int whole_shininess(float n) {
    return n >= 1.0f && n <= 1024.0f && std::floor(n) == n ? static_cast<int>(n) : 0;
}

}  // namespace

SimdMaterial::SimdMaterial(Color ka_, Color kd_, Color ks_, float shininess_, bool blinn_,
                           bool specular_)
    : ka(ka_),
      kd(kd_),
      ks(ks_),
      shininess(shininess_),
      blinn(blinn_),
      specular(specular_),
      norm(phong_lobe_norm(shininess_, blinn_)),
      whole(whole_shininess(shininess_)),
      tiny(whole > 0 ? std::exp2(-100.0f / static_cast<float>(whole)) : 0.0f) {}

#if SVETLO_SIMD
int simd_lanes() { return cpu_has_avx2() ? 8 : 4; }

void pow4(const float x[4], const float n[4], float out[4]) {
    _mm_storeu_ps(out, pow_ps(_mm_loadu_ps(x), _mm_loadu_ps(n)));
}

void shade_batch(const ShadeBatch& b, const SimdLights& lights, vec3 eye, bool ortho, vec3 forward,
                 Color ambient, Color* out, const LightVisibility& vis) {
#ifdef SVETLO_HAS_AVX2_KERNEL
    if (cpu_has_avx2() && b.count > 4) {
        shade_batch_avx2(b, lights, eye, ortho, forward, ambient, vis, out);
        return;
    }
#endif
    for (int first = 0; first < b.count; first += 4) {
        shade_batch_kernel(b, first, lights, eye, ortho, forward, ambient, vis, out);
    }
}

void shade_run(const TriangleRun& q, float dl1, float dl2, int groups, const SimdMaterial& mat,
               vec3 ng, const SimdLights& lights, vec3 eye, bool ortho, vec3 forward, Color ambient,
               Color* out, int lanes, const LightVisibility& vis) {
    int first = 0;
#ifdef SVETLO_HAS_AVX2_KERNEL
    if (lanes != 4 && cpu_has_avx2() && groups >= 2) {
        // Eight lanes where the processor has them; a last group of four with four.
        int eights = groups / 2;
        shade_run_avx2(q, dl1, dl2, 0, eights, mat, ng, lights, eye, ortho, forward, ambient, vis,
                       out);
        first = 8 * eights;
    }
#endif
    int left = groups - first / 4;
    shade_run_kernel(q, dl1, dl2, first, left, mat, ng, lights, eye, ortho, forward, ambient, vis,
                     out + first);
}

#endif

}  // namespace svetlo
