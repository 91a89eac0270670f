// The shadow maps' filters (shadow_map_filters.h): one texel compared, percentage-closer
// filtering, and percentage-closer soft shadows.
#include "svetlo/raster/shadow_map_filters.h"

#if SVETLO_SIMD
#include <immintrin.h>
#endif

#include <algorithm>

namespace svetlo::raster {

int margin_texels(const ShadowMapSettings& sm, int res) {
    int m = sm.filter == ShadowFilter::Pcss ? std::max(res / 16, sm.kernel) : sm.kernel / 2 + 2;
    return std::clamp(m, 0, std::max(0, res / 4));
}

namespace {

/// Four texels around pixel position px, compared and weighted bilinearly.
float bilinear(const DepthMap& m, vec2 px, float receiver, float bias) {
    vec2 t = px - vec2(0.5f);
    int x = static_cast<int>(std::floor(t.x)), y = static_cast<int>(std::floor(t.y));
    float fx = t.x - static_cast<float>(x), fy = t.y - static_cast<float>(y);
    float a = shadow_compare(m.at(x, y), receiver, bias),
          b = shadow_compare(m.at(x + 1, y), receiver, bias);
    float c = shadow_compare(m.at(x, y + 1), receiver, bias),
          d = shadow_compare(m.at(x + 1, y + 1), receiver, bias);
    return (a * (1.0f - fx) + b * fx) * (1.0f - fy) + (c * (1.0f - fx) + d * fx) * fy;
}

}  // namespace

namespace twin {

float pcf_block(const float* d, int res, int n, float fx, float fy, float limit) {
    float sum = 0.0f;
    for (int v = 0; v <= n; ++v, d += res) {
        const float wy = v == 0 ? 1.0f - fy : v == n ? fy : 1.0f;
        // Lit texels of the row: the inner ones count 1, the two ends by the fractions.
        float row = 0.0f;
        for (int u = 1; u < n; ++u) row += d[u] >= limit ? 1.0f : 0.0f;
        row += (d[0] >= limit ? 1.0f - fx : 0.0f) + (d[n] >= limit ? fx : 0.0f);
        sum += wy * row;
    }
    return sum;
}

}  // namespace twin

#if SVETLO_SIMD
namespace sse {

float pcf_block(const float* d, int res, int n, float fx, float fy, float limit) {
    // A row's n + 1 texels in one four-wide load, weighted (1 - fx, 1, ..., fx, 0): the sum of
    // the twin, in another order.
    const __m128 at = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f);
    const __m128 inner = _mm_and_ps(_mm_cmpgt_ps(at, _mm_setzero_ps()),
                                    _mm_cmplt_ps(at, _mm_set1_ps(static_cast<float>(n))));
    const __m128 wx = _mm_or_ps(
        _mm_and_ps(inner, _mm_set1_ps(1.0f)),
        _mm_or_ps(
            _mm_and_ps(_mm_cmpeq_ps(at, _mm_setzero_ps()), _mm_set1_ps(1.0f - fx)),
            _mm_and_ps(_mm_cmpeq_ps(at, _mm_set1_ps(static_cast<float>(n))), _mm_set1_ps(fx))));
    const __m128 lim = _mm_set1_ps(limit);
    __m128 total = _mm_setzero_ps();
    for (int v = 0; v <= n; ++v, d += res) {
        const float wy = v == 0 ? 1.0f - fy : v == n ? fy : 1.0f;
        const __m128 lit = _mm_and_ps(_mm_cmpge_ps(_mm_loadu_ps(d), lim), wx);
        total = _mm_add_ps(total, _mm_mul_ps(lit, _mm_set1_ps(wy)));
    }
    const __m128 pair = _mm_add_ps(total, _mm_movehl_ps(total, total));
    return _mm_cvtss_f32(_mm_add_ss(pair, _mm_shuffle_ps(pair, pair, 1)));
}

}  // namespace sse
#endif

float shadow_pcf(const DepthMap& m, const ShadowMapSettings& settings, vec2 px, float receiver,
                 float radius, float slope) {
    const int n = settings.kernel;
    const float step = n > 1 ? 2.0f * radius / static_cast<float>(n - 1) : 0.0f;
    const float bias = settings.bias + slope * (radius + 1.0f);
    if (n > 1 && step == 1.0f) {
        // Taps one texel apart share their bilinear fractions: their n^2 bilinear
        // comparisons add up to (n + 1)^2 comparisons weighted 1 inside and by the
        // fractions on the border (the same sum, each texel compared once).
        const vec2 base = px - vec2(0.5f + radius);
        const int x0 = static_cast<int>(std::floor(base.x)),
                  y0 = static_cast<int>(std::floor(base.y));
        const float fx = base.x - static_cast<float>(x0), fy = base.y - static_cast<float>(y0);
        const float limit = receiver - bias;
        const bool inside = x0 >= 0 && y0 >= 0 && x0 + n < m.res && y0 + n < m.res;
        if (inside) {
            const float* d = m.distance.data() +
                             static_cast<size_t>(y0) * static_cast<size_t>(m.res) +
                             static_cast<size_t>(x0);
#if SVETLO_SIMD
            if (n <= 3 && x0 + 3 < m.res)
                return sse::pcf_block(d, m.res, n, fx, fy, limit) / static_cast<float>(n * n);
#endif
            return twin::pcf_block(d, m.res, n, fx, fy, limit) / static_cast<float>(n * n);
        }
        // Near the map's edge: each texel through m.at, which repeats the edge.
        float sum = 0.0f;
        for (int v = 0; v <= n; ++v) {
            const float wy = v == 0 ? 1.0f - fy : v == n ? fy : 1.0f;
            float row = 0.0f;
            for (int u = 0; u <= n; ++u) {
                const float wx = u == 0 ? 1.0f - fx : u == n ? fx : 1.0f;
                row += wx * shadow_compare(m.at(x0 + u, y0 + v), receiver, bias);
            }
            sum += wy * row;
        }
        return sum / static_cast<float>(n * n);
    }
    float sum = 0.0f;
    for (int v = 0; v < n; ++v) {
        for (int u = 0; u < n; ++u) {
            vec2 o(static_cast<float>(u) * step - radius, static_cast<float>(v) * step - radius);
            sum += bilinear(m, px + o, receiver, bias);
        }
    }
    return sum / static_cast<float>(n * n);
}

float shadow_pcss(const DepthMap& m, const ShadowMapSettings& settings, float size, vec2 px,
                  float receiver, float slope) {
    const float max_radius = static_cast<float>(margin_texels(settings, m.res));
    // Blockers lie in the cone from the receiver to the light: at the near plane, the
    // light's half-width times (d_r - near) / (d_r near), in tan units.
    const float near = m.cam.near;
    float search = 0.5f * size * (receiver - near) / (receiver * near) / m.texel;
    search = std::min(search, max_radius);
    const int n = settings.kernel;
    const float step = n > 1 ? 2.0f * search / static_cast<float>(n - 1) : 0.0f;
    float blockers = 0.0f, count = 0.0f;
    for (int v = 0; v < n; ++v) {
        for (int u = 0; u < n; ++u) {
            vec2 o(static_cast<float>(u) * step - search, static_cast<float>(v) * step - search);
            float d = m.at(static_cast<int>(px.x + o.x), static_cast<int>(px.y + o.y));
            if (d < receiver - settings.bias - slope * (search + 1.0f)) {
                blockers += d;
                count += 1.0f;
            }
        }
    }
    if (count == 0.0f) return 1.0f;
    const float blocker = blockers / count;
    // The penumbra's half-width at the receiver, W (d_r - d_b) / (2 d_b), in tan units.
    float radius = 0.5f * size * (receiver - blocker) / (blocker * receiver) / m.texel;
    radius = std::clamp(radius, 0.5f, max_radius);
    // A penumbra many texels wide, filtered by a regular grid of taps, shows the grid as
    // bands: the taps lie instead on a Vogel (golden-angle) disc, turned by an angle that
    // depends on the receiver's texel, which trades the bands for fine, fixed noise.
    const int taps = n * n;
    const float bias = settings.bias + slope * (radius + 1.0f);
    const auto cell = glm::ivec2(glm::floor(px));
    const uint32_t h =
        (static_cast<uint32_t>(cell.x) * 73856093u) ^ (static_cast<uint32_t>(cell.y) * 19349663u);
    const float turn = static_cast<float>((h * 2654435761u) >> 8) * (6.2831853f / 16777216.0f);
    constexpr float kGolden = 2.39996323f;  // radians
    float sum = 0.0f;
    for (int k = 0; k < taps; ++k) {
        float r = radius * std::sqrt((static_cast<float>(k) + 0.5f) / static_cast<float>(taps));
        float a = static_cast<float>(k) * kGolden + turn;
        sum += bilinear(m, px + r * vec2(std::cos(a), std::sin(a)), receiver, bias);
    }
    return sum / static_cast<float>(taps);
}

}  // namespace svetlo::raster
