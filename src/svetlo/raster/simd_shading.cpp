#include "svetlo/raster/simd_shading.h"

#include <immintrin.h>

namespace svetlo {

namespace {

using V = __m128;

V set(float a) { return _mm_set1_ps(a); }
V add(V a, V b) { return _mm_add_ps(a, b); }
V sub(V a, V b) { return _mm_sub_ps(a, b); }
V mul(V a, V b) { return _mm_mul_ps(a, b); }
V vmax(V a, V b) { return _mm_max_ps(a, b); }
V select(V mask, V a, V b) { return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b)); }

struct V3 {
    V x, y, z;
};
V3 sub3(V3 a, V3 b) { return {sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z)}; }
V3 scale3(V3 a, V s) { return {mul(a.x, s), mul(a.y, s), mul(a.z, s)}; }
V dot3(V3 a, V3 b) { return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z)); }
V3 neg3(V3 a) {
    return {sub(_mm_setzero_ps(), a.x), sub(_mm_setzero_ps(), a.y), sub(_mm_setzero_ps(), a.z)};
}
V3 select3(V mask, V3 a, V3 b) {
    return {select(mask, a.x, b.x), select(mask, a.y, b.y), select(mask, a.z, b.z)};
}
/// 1 / x and 1 / sqrt(x): the 12-bit hardware estimates refined by one Newton-Raphson step
/// (about 22 bits, well within the 1e-5 the fast path promises; a true division or square
/// root costs several times more).
V rcp(V x) {
    V r = _mm_rcp_ps(x);
    return mul(r, sub(set(2.0f), mul(x, r)));
}
V rsqrt(V x) {
    V r = _mm_rsqrt_ps(x);
    return mul(r, sub(set(1.5f), mul(mul(set(0.5f), x), mul(r, r))));
}
V3 normalize3(V3 a) { return scale3(a, rsqrt(dot3(a, a))); }

/// log2(x) for x > 0: x = 2^e m with m in [sqrt(1/2), sqrt(2)), then
/// ln m = 2 atanh(z) = 2 (z + z^3/3 + z^5/5 + z^7/7 + z^9/9), z = (m - 1) / (m + 1), |z| < 0.172.
V log2_ps(V x) {
    __m128i bits = _mm_castps_si128(x);
    __m128i e = _mm_sub_epi32(_mm_srli_epi32(bits, 23), _mm_set1_epi32(127));
    V m = _mm_castsi128_ps(
        _mm_or_si128(_mm_and_si128(bits, _mm_set1_epi32(0x007fffff)), _mm_set1_epi32(0x3f800000)));
    V big = _mm_cmpgt_ps(m, set(1.41421356f));
    m = select(big, mul(m, set(0.5f)), m);
    V ef = add(_mm_cvtepi32_ps(e), _mm_and_ps(big, set(1.0f)));
    V z = mul(sub(m, set(1.0f)), rcp(add(m, set(1.0f))));
    V z2 = mul(z, z);
    V poly = add(set(1.0f / 7.0f), mul(z2, set(1.0f / 9.0f)));
    poly = add(set(1.0f / 5.0f), mul(z2, poly));
    poly = add(set(1.0f / 3.0f), mul(z2, poly));
    poly = add(set(1.0f), mul(z2, poly));
    V ln_m = mul(mul(set(2.0f), z), poly);
    return add(ef, mul(ln_m, set(1.44269504088896341f)));
}

/// 2^y: y = i + f with i = round(y), |f| <= 1/2, 2^f = e^(f ln 2) by its Taylor series to the
/// 7th power (error below 1e-8), 2^i through the exponent bits. y is clamped to [-126, 127].
V exp2_ps(V y) {
    y = _mm_min_ps(_mm_max_ps(y, set(-126.0f)), set(127.0f));
    __m128i i = _mm_cvtps_epi32(y);  // round to nearest
    V f = sub(y, _mm_cvtepi32_ps(i));
    V t = mul(f, set(0.693147180559945309f));
    V p = add(set(1.0f / 5040.0f), mul(t, set(1.0f / 40320.0f)));
    p = add(set(1.0f / 720.0f), mul(t, p));
    p = add(set(1.0f / 120.0f), mul(t, p));
    p = add(set(1.0f / 24.0f), mul(t, p));
    p = add(set(1.0f / 6.0f), mul(t, p));
    p = add(set(0.5f), mul(t, p));
    p = add(set(1.0f), mul(t, p));
    p = add(set(1.0f), mul(t, p));
    V scale = _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(i, _mm_set1_epi32(127)), 23));
    return mul(p, scale);
}

/// x^n for x >= 0, n >= 0 (0^0 = 1, as std::pow).
V pow_ps(V x, V n) {
    V positive = _mm_cmpgt_ps(x, _mm_setzero_ps());
    V r = exp2_ps(mul(n, log2_ps(vmax(x, set(1e-38f)))));
    V zero_n = _mm_cmpeq_ps(n, _mm_setzero_ps());
    return select(zero_n, set(1.0f), _mm_and_ps(positive, r));
}

V lane(const float (&a)[4]) { return _mm_loadu_ps(a); }

}  // namespace

void pow4(const float x[4], const float n[4], float out[4]) {
    _mm_storeu_ps(out, pow_ps(_mm_loadu_ps(x), _mm_loadu_ps(n)));
}

namespace {

/// The lighting of four samples: positions p, interpolated normals ns (any length), unit
/// geometric normals ng (counter-clockwise side); material terms per lane.
struct Material4 {
    V ka[3], kd[3], ks[3], shininess, norm, blinn;  // ka premultiplied by the ambient, kd by 1/pi
};

void light4(V3 p, V3 ns, V3 ng, const Material4& m, const SimdLights& lights, vec3 eye, bool ortho,
            vec3 forward, V L[3]) {
    V3 wo = ortho ? V3{set(-forward.x), set(-forward.y), set(-forward.z)}
                  : normalize3(sub3(V3{set(eye.x), set(eye.y), set(eye.z)}, p));
    // Two-sided: both normals toward the viewer; an interpolated normal facing away falls back
    // to the geometric one (as light_point does).
    V facing = _mm_cmpge_ps(dot3(ng, wo), _mm_setzero_ps());
    V3 n = select3(facing, ng, neg3(ng));
    V len2 = dot3(ns, ns);
    V has_ns = _mm_cmpgt_ps(len2, _mm_setzero_ps());
    ns = select3(has_ns, scale3(ns, rsqrt(vmax(len2, set(1e-30f)))), n);
    ns = select3(_mm_cmplt_ps(dot3(ns, n), _mm_setzero_ps()), neg3(ns), ns);
    ns = select3(_mm_cmple_ps(dot3(ns, wo), _mm_setzero_ps()), n, ns);
    V cos_o = dot3(ns, wo);
    V lit_o = _mm_cmpgt_ps(cos_o, _mm_setzero_ps());
    for (int c = 0; c < 3; ++c) L[c] = m.ka[c];
    auto contribute = [&](V3 wi, const V irr[3]) {
        V cos_i = dot3(ns, wi);
        V ok = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(cos_i, _mm_setzero_ps()),
                                     _mm_cmpgt_ps(dot3(n, wi), _mm_setzero_ps())),
                          lit_o);
        if (_mm_movemask_ps(ok) == 0) return;
        // Phong: r.v with r = 2 (n.wi) n - wi; Blinn-Phong: n.h with h = normalize(wi + wo).
        V rv = sub(mul(mul(set(2.0f), cos_i), cos_o), dot3(wi, wo));
        V3 h = normalize3(V3{add(wi.x, wo.x), add(wi.y, wo.y), add(wi.z, wo.z)});
        V x = vmax(select(m.blinn, dot3(ns, h), rv), _mm_setzero_ps());
        V spec = mul(m.norm, pow_ps(x, m.shininess));
        for (int c = 0; c < 3; ++c) {
            V f = add(m.kd[c], mul(m.ks[c], spec));
            L[c] = add(L[c], _mm_and_ps(ok, mul(mul(f, irr[c]), cos_i)));
        }
    };
    for (const SimdLights::Point& light : lights.points) {
        V3 d = sub3(V3{set(light.position.x), set(light.position.y), set(light.position.z)}, p);
        V d2 = dot3(d, d);
        V inv_d = rsqrt(d2);
        V3 wi = scale3(d, inv_d);
        V inv_d2 = mul(inv_d, inv_d);
        V irr[3] = {mul(set(light.intensity.r), inv_d2), mul(set(light.intensity.g), inv_d2),
                    mul(set(light.intensity.b), inv_d2)};
        contribute(wi, irr);
    }
    for (const SimdLights::Directional& light : lights.directionals) {
        V3 wi{set(light.to_light.x), set(light.to_light.y), set(light.to_light.z)};
        V irr[3] = {set(light.irradiance.r), set(light.irradiance.g), set(light.irradiance.b)};
        contribute(wi, irr);
    }
}

float norm_of(const SimdMaterial& m) {
    return m.blinn ? (m.shininess + 8.0f) / (8.0f * kPi) : (m.shininess + 2.0f) / (2.0f * kPi);
}

void store(const V L[3], int count, Color out[4]) {
    float r[4], g[4], b[4];
    _mm_storeu_ps(r, L[0]);
    _mm_storeu_ps(g, L[1]);
    _mm_storeu_ps(b, L[2]);
    for (int k = 0; k < count; ++k) out[k] = Color(r[k], g[k], b[k]);
}

}  // namespace

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
    Material4 m;
    for (int c = 0; c < 3; ++c) {
        m.ka[c] = lane(ka[c]);
        m.kd[c] = lane(kd[c]);
        m.ks[c] = lane(ks[c]);
    }
    m.shininess = lane(shin);
    m.norm = lane(norm);
    m.blinn = _mm_cmpgt_ps(lane(blinn), _mm_setzero_ps());
    V L[3];
    light4(V3{lane(px), lane(py), lane(pz)}, V3{lane(nx), lane(ny), lane(nz)},
           V3{lane(gx), lane(gy), lane(gz)}, m, lights, eye, ortho, forward, L);
    store(L, b.count, out);
}

namespace {

Material4 broadcast(const SimdMaterial& mat, Color ambient) {
    Material4 m;
    for (int c = 0; c < 3; ++c) {
        m.ka[c] = set(mat.ka[c] * ambient[c]);
        m.kd[c] = set(mat.kd[c] * kInvPi);
        m.ks[c] = set(mat.specular ? mat.ks[c] : 0.0f);
    }
    m.shininess = set(mat.shininess);
    m.norm = set(norm_of(mat));
    m.blinn = mat.blinn ? _mm_castsi128_ps(_mm_set1_epi32(-1)) : _mm_setzero_ps();
    return m;
}

/// Perspective-correct interpolation from screen barycentrics and lighting of four samples.
void shade_weights(V l1, V l2, const TriangleRun& q, const Material4& m, vec3 ng,
                   const SimdLights& lights, vec3 eye, bool ortho, vec3 forward, V L[3]) {
    // q_i = l_i / w_i, b_i = q_i / sum.
    V l0 = sub(sub(set(1.0f), l1), l2);
    V q0 = mul(l0, set(q.invw[0])), q1 = mul(l1, set(q.invw[1])), q2 = mul(l2, set(q.invw[2]));
    V inv = rcp(add(add(q0, q1), q2));
    V b0 = mul(q0, inv), b1 = mul(q1, inv), b2 = mul(q2, inv);
    auto lerp3 = [&](const vec3(&v)[3]) {
        return V3{add(add(mul(b0, set(v[0].x)), mul(b1, set(v[1].x))), mul(b2, set(v[2].x))),
                  add(add(mul(b0, set(v[0].y)), mul(b1, set(v[1].y))), mul(b2, set(v[2].y))),
                  add(add(mul(b0, set(v[0].z)), mul(b1, set(v[1].z))), mul(b2, set(v[2].z)))};
    };
    light4(lerp3(q.world), lerp3(q.normal), V3{set(ng.x), set(ng.y), set(ng.z)}, m, lights, eye,
           ortho, forward, L);
}

}  // namespace

void shade_run(const TriangleRun& q, float dl1, float dl2, int groups, const SimdMaterial& mat,
               vec3 ng, const SimdLights& lights, vec3 eye, bool ortho, vec3 forward, Color ambient,
               Color* out) {
    Material4 m = broadcast(mat, ambient);
    const V steps = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f);
    for (int g = 0; g < groups; ++g) {
        // l = l_start + dl * index, from the start each time: no drift along the run.
        V index = add(set(4.0f * static_cast<float>(g)), steps);
        V l1 = add(set(q.l1), mul(set(dl1), index));
        V l2 = add(set(q.l2), mul(set(dl2), index));
        V L[3];
        shade_weights(l1, l2, q, m, ng, lights, eye, ortho, forward, L);
        store(L, 4, out + 4 * g);
    }
}

}  // namespace svetlo
