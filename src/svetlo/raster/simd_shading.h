// Four samples lit at once with SSE: the rasterizer's fast path for the commonest case, a
// constant Lambert, Phong or Blinn-Phong material under point, spot and directional lights and
// the VPLs of lights with area. It
// computes exactly the formulas of shading/bsdf.cpp and raster_lights.cpp (two-sided normals,
// E = I cos / d^2, f = kd/pi + ks (n+2)/(2 pi) (r.v)^n or ks (n+8)/(8 pi) (n.h)^n, plus
// ka * ambient), four lanes per instruction. pow is exp2(n log2 x) with polynomials accurate
// to about 1e-7 relative (Cody and Waite style range reduction), or repeated squaring when n
// is a whole number shared by the lanes, where the scalar path calls powf: the two paths
// agree to within 1e-5 relative.
#pragma once

#include <vector>

#include "svetlo/core/math.h"
#include "svetlo/scene/scene.h"

namespace svetlo {

/// The lights the fast path handles (nothing else may light the frame).
struct SimdLights {
    struct Point {
        vec3 position;
        Color intensity;  // W/sr
        uint32_t source;  // its index in the light set: its row of a LightVisibility
    };
    struct Directional {
        vec3 to_light;     // unit, opposite to the direction of travel
        Color irradiance;  // W/m^2
        uint32_t source;
    };
    /// A spot light: a point light times the cone's smoothstep (shading/lights.h,
    /// spot_cone_factor) between cos_outer and cos_inner of the angle from its axis.
    struct Spot {
        vec3 position;
        vec3 axis;  // unit
        Color intensity;
        float cos_outer;
        float inv_width;  // 1 / (cos_inner - cos_outer), or a large number for a hard cone
        uint32_t source;
    };
    /// One of the n virtual point lights of a light with area (raster_lights.h), which
    /// together give the mean of E = L cos' / (max(d^2, min_dist2) pdf_area) on the emitter's
    /// front side (LightSet::sample_at), nothing behind it.
    struct Vpl {
        vec3 position;
        vec3 normal;          // unit, the emitting side
        Color radiance_area;  // L / (pdf_area n), W/sr
        float min_dist2;      // m^2: d^2 is clamped to the area the point stands for
        uint32_t source;
    };
    std::vector<Point> points;
    std::vector<Directional> directionals;
    std::vector<Spot> spots;
    std::vector<Vpl> vpls;
};

/// The visibility V in [0, 1] of each light at each sample of a tile (a shadow technique's
/// mask): row `source` (the light set's index) of `stride` samples. Null: every light visible.
struct LightVisibility {
    const float* v = nullptr;
    size_t stride = 0;
    float at(size_t source, size_t sample) const { return v ? v[source * stride + sample] : 1.0f; }
};

/// A constant material in the fast path's terms, with what the kernel derives from it once.
struct SimdMaterial {
    SimdMaterial(Color ka, Color kd, Color ks, float shininess, bool blinn, bool specular);
    const Color ka, kd, ks;
    const float shininess;
    const bool blinn;
    const bool specular;  // false for Lambert (ks = 0)
    const float norm;     // the lobe's normalisation: (n + 2) / (2 pi), or (n + 8) / (8 pi)
    const int whole;      // n when it is a whole number in [1, 1024] (powers by squaring), else 0
    const float tiny;     // 2^(-100 / whole): smaller bases make lobes below 2^-100, taken as 0
};

/// Up to eight samples, one lane each (x, y, z arrays, as the kernel loads them): position,
/// interpolated normal (not necessarily unit), the geometric normal of the counter-clockwise
/// side (any length; a zero one stands for (0, 0, 1)), and the material. A lane of a textured
/// material brings its own colours, the material's textures evaluated at the sample
/// (`colours`: ka, kd, ks), which replace the material's.
struct ShadeBatch {
    static constexpr int kCapacity = 8;
    int count = 0;
    float p[3][kCapacity], ns[3][kCapacity], ng[3][kCapacity];
    const SimdMaterial* material[kCapacity] = {};
    uint32_t sample[kCapacity] = {};  // each lane's sample in the tile (for the visibility)
    bool own[kCapacity] = {};         // whether the lane has its own colours
    Color own_colours[kCapacity][3];  // and those: ka, kd, ks

    /// Appends a sample; the caller flushes a full batch.
    void add(vec3 position, vec3 normal, vec3 geometric, const SimdMaterial* m, uint32_t s = 0,
             const Color* colours = nullptr) {
        for (int c = 0; c < 3; ++c) {
            p[c][count] = position[c];
            ns[c][count] = normal[c];
            ng[c][count] = geometric[c];
        }
        sample[count] = s;
        own[count] = colours != nullptr;
        if (colours) {
            for (int k = 0; k < 3; ++k) own_colours[count][k] = colours[k];
        }
        material[count++] = m;
    }
};

/// Radiance toward the camera at each sample of the batch (eight lanes at once with AVX2,
/// else four at a time), each light's term times its visibility at the lane's sample.
void shade_batch(const ShadeBatch& batch, const SimdLights& lights, vec3 eye, bool ortho,
                 vec3 forward, Color ambient, Color* out, const LightVisibility& vis = {});

/// Samples of one triangle: the screen barycentrics of vertices 1 and 2 of the first, and the
/// triangle's 1/w, world positions and normals per vertex.
struct TriangleRun {
    float l1 = 0.0f, l2 = 0.0f;
    float invw[3];
    vec3 world[3], normal[3];
    uint32_t first_sample = 0;  // the run's first sample in the tile (for the visibility)
    /// A textured material's colours at each sample of the run, from its first: ka, kd, ks,
    /// which replace the material's (as a batch lane's own colours); null: the material's.
    const Color (*own)[3] = nullptr;
};

/// A run of 4 `groups` consecutive samples of one triangle along a row: the weights of the
/// first are q.l1 and q.l2, and they change by dl1, dl2 from one sample to the next; ng as in
/// ShadeBatch.
/// Writes 4 groups colours to `out`, eight lanes at a time where the processor has AVX2
/// (simd_lanes()) unless `lanes` is 4 (the tests of the four-lane build ask for it).
void shade_run(const TriangleRun& q, float dl1, float dl2, int groups, const SimdMaterial& m,
               vec3 ng, const SimdLights& lights, vec3 eye, bool ortho, vec3 forward, Color ambient,
               Color* out, int lanes = 0, const LightVisibility& vis = {});

/// The lanes shade_run uses on this processor: 8 with AVX2, else 4.
int simd_lanes();

/// exp2(n log2(x)) on four lanes, for the tests: x >= 0, n >= 0; 0^n is 0 for n > 0, 1 for 0.
void pow4(const float x[4], const float n[4], float out[4]);

}  // namespace svetlo
