#include "svetlo/raster/simd_shading.h"

#include <immintrin.h>

namespace svetlo {

#define SVETLO_SIMD_WIDTH 4
#include "svetlo/raster/simd_kernel.inc"

// The AVX2 build of the kernel (simd_shading_avx2.cpp), when the compiler made one.
#ifdef SVETLO_HAS_AVX2_KERNEL
void shade_run_avx2(const TriangleRun& q, float dl1, float dl2, int first, int groups,
                    const SimdMaterial& mat, vec3 ng, const SimdLights& lights, vec3 eye,
                    bool ortho, vec3 forward, Color ambient, Color* out);
#endif

namespace {

bool cpu_has_avx2() {
#ifdef SVETLO_HAS_AVX2_KERNEL
    static const bool has = __builtin_cpu_supports("avx2") != 0;
    return has;
#else
    return false;
#endif
}

V lane(const float (&a)[4]) { return _mm_loadu_ps(a); }

}  // namespace

int simd_lanes() { return cpu_has_avx2() ? 8 : 4; }

void pow4(const float x[4], const float n[4], float out[4]) {
    _mm_storeu_ps(out, pow_ps(_mm_loadu_ps(x), _mm_loadu_ps(n)));
}

void shade_batch(const ShadeBatch& b, const SimdLights& lights, vec3 eye, bool ortho, vec3 forward,
                 Color ambient, Color out[4]) {
    // Gather the lanes (unused lanes repeat lane 0).
    float px[4], py[4], pz[4], nx[4], ny[4], nz[4], gx[4], gy[4], gz[4];
    float ka[3][4], kd[3][4], ks[3][4], shin[4], norm[4], blinn[4];
    for (int k = 0; k < 4; ++k) {
        int s = k < b.count ? k : 0;
        const SimdMaterial& m = *b.material[s];
        px[k] = b.p[s].x, py[k] = b.p[s].y, pz[k] = b.p[s].z;
        nx[k] = b.ns[s].x, ny[k] = b.ns[s].y, nz[k] = b.ns[s].z;
        gx[k] = b.ng[s].x, gy[k] = b.ng[s].y, gz[k] = b.ng[s].z;
        for (int c = 0; c < 3; ++c) {
            ka[c][k] = m.ka[c] * ambient[c];
            kd[c][k] = m.kd[c] * kInvPi;
            ks[c][k] = m.specular ? m.ks[c] : 0.0f;
        }
        shin[k] = m.shininess;
        norm[k] = norm_of(m);
        blinn[k] = m.blinn ? 1.0f : 0.0f;
    }
    MaterialV m;
    for (int c = 0; c < 3; ++c) {
        m.ka[c] = lane(ka[c]);
        m.kd[c] = lane(kd[c]);
        m.ks[c] = lane(ks[c]);
    }
    m.shininess = lane(shin);
    m.norm = lane(norm);
    m.blinn = gt(lane(blinn), zero());
    V L[3];
    light(V3{lane(px), lane(py), lane(pz)}, V3{lane(nx), lane(ny), lane(nz)},
          V3{lane(gx), lane(gy), lane(gz)}, m, lights, eye, ortho, forward, L);
    store(L, b.count, out);
}

void shade_run(const TriangleRun& q, float dl1, float dl2, int groups, const SimdMaterial& mat,
               vec3 ng, const SimdLights& lights, vec3 eye, bool ortho, vec3 forward, Color ambient,
               Color* out, int lanes) {
    int first = 0;
#ifdef SVETLO_HAS_AVX2_KERNEL
    if (lanes != 4 && cpu_has_avx2() && groups >= 2) {
        // Eight lanes where the processor has them; a last group of four with four.
        int eights = groups / 2;
        shade_run_avx2(q, dl1, dl2, 0, eights, mat, ng, lights, eye, ortho, forward, ambient, out);
        first = 8 * eights;
    }
#endif
    int left = groups - first / 4;
    shade_run_kernel(q, dl1, dl2, first, left, mat, ng, lights, eye, ortho, forward, ambient,
                     out + first);
}

}  // namespace svetlo
