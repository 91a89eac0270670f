// Where a shadow-map lookup falls (shadow_lookup.h): the twin one sample at a time, and its
// SSE form four samples at a time, the same operations in the same order.
#include "svetlo/raster/shadow_lookup.h"

#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>

#include "svetlo/core/bit_cast.h"

namespace svetlo::raster {

namespace twin {

ShadowLookup shadow_lookup(const ShadowMapSettings& settings, const ShadowCaster& c,
                           const DepthMap& m, const ShadowSample& s) {
    // The direction to the light and a texel's width at the receiver.
    const vec3 wi = m.cam.orthographic ? -c.direction : (m.cam.eye - s.p) / m.receiver(s.p);
    const float texel = m.texel_at(m.receiver(s.p));
    // Normal offset: the lookup point moves off the surface by normal_offset texels.
    const vec3 q = s.p + s.n * (settings.normal_offset * texel);
    // clip = view_projection (q, 1): columns times coordinates, added in this order.
    const mat4& vp = m.view_projection;
    auto clip = [&](int r) {
        return ((vp[0][r] * q.x + vp[1][r] * q.y) + vp[2][r] * q.z) + vp[3][r];
    };
    const float w = clip(3), res = static_cast<float>(m.res);
    ShadowLookup out;
    out.receiver = m.receiver(q);
    // CameraMatrices::to_pixels of the clip point's xy / w.
    out.x = (clip(0) / w + 1.0f) * 0.5f * res;
    out.y = (1.0f - clip(1) / w) * 0.5f * res;
    // Outside a spot's cone (behind its map, or off it), or beyond the fitted view.
    out.on_map = w > 0.0f && out.x >= 0.0f && out.y >= 0.0f && out.x <= res && out.y <= res;
    // Slope-scaled: the depth of the receiver's plane changes by tan(theta) texels per
    // texel of offset.
    const float cos_theta = std::min(std::max(glm::dot(s.n, wi), 0.1f), 1.0f);
    const float tan_theta = std::sqrt(1.0f - cos_theta * cos_theta) / cos_theta;
    out.slope = settings.slope_bias * texel * tan_theta;
    return out;
}

}  // namespace twin

#if SVETLO_SIMD
namespace sse {

void shadow_lookup4(const ShadowMapSettings& settings, const ShadowCaster& c, const DepthMap& m,
                    const ShadowSample* const s[4], ShadowLookup out[4]) {
    using V = __m128;
    auto set1 = [](float x) { return _mm_set1_ps(x); };
    auto add = [](V a, V b) { return _mm_add_ps(a, b); };
    auto sub = [](V a, V b) { return _mm_sub_ps(a, b); };
    auto mul = [](V a, V b) { return _mm_mul_ps(a, b); };
    auto div = [](V a, V b) { return _mm_div_ps(a, b); };
    auto dot = [&](const V a[3], const V b[3]) {
        return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]));
    };
    const vec3 eye = m.cam.eye, forward = m.cam.forward;
    const mat4& vp = m.view_projection;
    const float res = static_cast<float>(m.res);
    V p[3], n[3];
    for (int a = 0; a < 3; ++a) {
        p[a] = _mm_setr_ps(s[0]->p[a], s[1]->p[a], s[2]->p[a], s[3]->p[a]);
        n[a] = _mm_setr_ps(s[0]->n[a], s[1]->n[a], s[2]->n[a], s[3]->n[a]);
    }
    const V e[3] = {set1(eye.x), set1(eye.y), set1(eye.z)};
    const V fw[3] = {set1(forward.x), set1(forward.y), set1(forward.z)};
    const V d[3] = {sub(p[0], e[0]), sub(p[1], e[1]), sub(p[2], e[2])};
    V distance, wi[3], texel;
    if (m.cam.orthographic) {
        distance = dot(d, fw);
        for (int a = 0; a < 3; ++a) wi[a] = set1(-c.direction[a]);
        texel = set1(m.texel);
    } else {
        distance = _mm_sqrt_ps(dot(d, d));
        for (int a = 0; a < 3; ++a) wi[a] = div(sub(e[a], p[a]), distance);
        texel = mul(set1(m.texel), distance);
    }
    const V offset = mul(set1(settings.normal_offset), texel);
    const V q[3] = {add(p[0], mul(n[0], offset)), add(p[1], mul(n[1], offset)),
                    add(p[2], mul(n[2], offset))};
    const V dq[3] = {sub(q[0], e[0]), sub(q[1], e[1]), sub(q[2], e[2])};
    const V receiver = m.cam.orthographic ? dot(dq, fw) : _mm_sqrt_ps(dot(dq, dq));
    // clip = view_projection (q, 1), as lookup() adds it.
    auto row = [&](int r) {
        return add(add(add(mul(set1(vp[0][r]), q[0]), mul(set1(vp[1][r]), q[1])),
                       mul(set1(vp[2][r]), q[2])),
                   set1(vp[3][r]));
    };
    const V w = row(3);
    const V x = mul(mul(add(div(row(0), w), set1(1.0f)), set1(0.5f)), set1(res));
    const V y = mul(mul(sub(set1(1.0f), div(row(1), w)), set1(0.5f)), set1(res));
    const V zero = _mm_setzero_ps(), size = set1(res);
    const V on_map = _mm_and_ps(
        _mm_and_ps(_mm_cmpgt_ps(w, zero), _mm_and_ps(_mm_cmpge_ps(x, zero), _mm_cmpge_ps(y, zero))),
        _mm_and_ps(_mm_cmple_ps(x, size), _mm_cmple_ps(y, size)));
    const V cos_theta = _mm_min_ps(_mm_max_ps(dot(n, wi), set1(0.1f)), set1(1.0f));
    const V tan_theta = div(_mm_sqrt_ps(sub(set1(1.0f), mul(cos_theta, cos_theta))), cos_theta);
    const V slope = mul(mul(set1(settings.slope_bias), texel), tan_theta);
    alignas(16) float xs[4], ys[4], rs[4], ss[4], ok[4];
    _mm_store_ps(xs, x);
    _mm_store_ps(ys, y);
    _mm_store_ps(rs, receiver);
    _mm_store_ps(ss, slope);
    _mm_store_ps(ok, on_map);
    for (int L = 0; L < 4; ++L)
        out[L] = ShadowLookup{xs[L], ys[L], rs[L], ss[L], svetlo::bit_cast<uint32_t>(ok[L]) != 0};
}

}  // namespace sse
#endif

}  // namespace svetlo::raster
