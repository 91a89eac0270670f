// Warps from the unit square [0,1)^2 to the domains the renderers sample, with their pdfs.
// Formulas from pbrt-v4, chapter A.5 (Pharr, Jakob, Humphreys 2023).
#pragma once

#include "svetlo/core/math.h"

namespace svetlo {

/// cos x and sin x for |x| <= pi/4 by their Taylor series to x^10 and x^9: the first terms
/// left out are below 2e-9, under float's rounding.
inline vec2 cos_sin_quarter(float x) {
    float x2 = x * x;
    float c =
        1.0f +
        x2 * (-1.0f / 2 +
              x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 - x2 * (1.0f / 3628800)))));
    float s =
        x *
        (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880)))));
    return {c, s};
}

/// Concentric map to the unit disk (Shirley and Chiu 1997): keeps strata compact. The point
/// at angle (pi/4) t or pi/2 - (pi/4) t, t in [-1, 1], through cos_sin_quarter and a swap,
/// chosen by selects: random u would mispredict a branch half of the time.
inline vec2 sample_disk_concentric(vec2 u) {
    vec2 o = 2.0f * u - vec2(1.0f);
    if (o.x == 0.0f && o.y == 0.0f) return vec2(0.0f);
    const bool near_x = std::abs(o.x) > std::abs(o.y);  // within 45 degrees of the x axis
    const float r = near_x ? o.x : o.y;
    const vec2 cs = cos_sin_quarter((kPi / 4.0f) * ((near_x ? o.y : o.x) / r));
    return r * (near_x ? cs : vec2(cs.y, cs.x));
}

/// Cosine-weighted direction about +z; pdf = cos(theta) / pi per steradian.
inline vec3 sample_cosine_hemisphere(vec2 u) {
    vec2 d = sample_disk_concentric(u);
    return vec3(d.x, d.y, safe_sqrt(1.0f - d.x * d.x - d.y * d.y));
}

/// Uniform point on the unit sphere; pdf = 1 / (4 pi) per steradian.
inline vec3 sample_uniform_sphere(vec2 u) {
    float z = 1.0f - 2.0f * u.x;
    float r = safe_sqrt(1.0f - z * z);
    float phi = 2.0f * kPi * u.y;
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

/// Uniform barycentrics (b0, b1) on a triangle (b2 = 1 - b0 - b1), Heitz 2019 low-distortion map.
inline vec2 sample_triangle(vec2 u) {
    // The lesser coordinate is halved and the greater moved by as much: u.x < u.y gives
    // (u.x / 2, u.y - u.x / 2), else (u.x - u.y / 2, u.y / 2). Without a branch, which the
    // random u mispredicted half of the time.
    float m = 0.5f * std::min(u.x, u.y);
    return vec2(u.x - m, u.y - m);
}

/// The k-th point of the R2 low-discrepancy sequence (Roberts 2018) in [0,1)^2.
inline vec2 r2_sequence(int k) {
    constexpr double g = 1.32471795724474602596;  // the plastic number
    double x = 0.5 + k / g, y = 0.5 + k / (g * g);
    return vec2(static_cast<float>(x - std::floor(x)), static_cast<float>(y - std::floor(y)));
}

/// Stratum `index` of `count` in the unit square, jittered by u: a sqrt(count) grid when count
/// is a perfect square, otherwise `count` strips along x with a free y.
inline vec2 stratified_sample(int index, int count, vec2 u) {
    if (count == 1) return u;  // the one stratum: the square itself
    int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(count))));
    if (side * side == count) {
        return vec2((static_cast<float>(index % side) + u.x) / static_cast<float>(side),
                    (static_cast<float>(index / side) + u.y) / static_cast<float>(side));
    }
    return vec2((static_cast<float>(index) + u.x) / static_cast<float>(count), u.y);
}

/// Multiple importance sampling (Veach and Guibas 1995): the power heuristic (beta = 2) for a
/// sample of the strategy with pdf `a` against the other's `b`, pdfs already multiplied by their
/// strategies' sample counts: a^2 / (a^2 + b^2), computed from the ratio of the smaller to the
/// larger, so that pdfs past 1e19 (a point at the horizon of an infinite plane sampling a light
/// edge-on) do not overflow to inf / inf.
inline float power_heuristic(float a, float b) {
    if (!(a > 0.0f)) return 0.0f;
    if (!(b > 0.0f)) return 1.0f;
    if (a == b) return 0.5f;  // infinite pdfs included
    if (a > b) {
        float r = b / a;
        return 1.0f / (1.0f + r * r);
    }
    float r = a / b;
    return r * r / (1.0f + r * r);
}

}  // namespace svetlo
