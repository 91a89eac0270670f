// ꟻLIP from its papers (flip.h). The pipeline, per pixel:
//   colour: linear RGB -> YCxCz (opponent space) -> contrast sensitivity filters -> linear
//     RGB clipped to the unit cube -> CIELAB with Hunt's adjustment -> HyAB distance,
//     raised to q_c = 0.7 and redistributed onto [0, 1] (95 % of the range for errors up to
//     40 % of the largest, green against blue);
//   features: edges and points of the achromatic channel (first and second derivatives of a
//     Gaussian whose peak-to-trough width is 0.082 degrees), the larger difference of their
//     magnitudes, raised to q_f = 0.5;
//   error = colour^(1 - features).
// Every filter is a product of one-dimensional kernels, so each runs as two passes (the
// double sums of the papers' 2D kernels factor exactly); borders repeat the edge pixel.
#include "svetlo/core/flip.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "svetlo/core/parallel.h"

namespace svetlo {

namespace {

constexpr float kPi = 3.14159265358979f;

/// One channel of an image, row-major.
struct Plane {
    int width = 0, height = 0;
    std::vector<float> v;
    Plane(int w, int h) : width(w), height(h), v(static_cast<size_t>(w) * h, 0.0f) {}
    float& at(int i, int j) { return v[static_cast<size_t>(j) * width + i]; }
    float at(int i, int j) const { return v[static_cast<size_t>(j) * width + i]; }
};

/// Convolves every row (`across` true) or every column with `k` (odd length, centred),
/// repeating the border pixels.
Plane convolve(const Plane& in, const std::vector<float>& k, bool across, int threads) {
    const int w = in.width, h = in.height, r = static_cast<int>(k.size() / 2);
    Plane out(w, h);
    parallel_ranges(
        static_cast<size_t>(h), threads,
        [&](size_t j0, size_t j1) {
            for (int j = static_cast<int>(j0); j < static_cast<int>(j1); ++j) {
                for (int i = 0; i < w; ++i) {
                    float s = 0.0f;
                    for (int d = -r; d <= r; ++d) {
                        s += k[d + r] * (across ? in.at(std::clamp(i + d, 0, w - 1), j)
                                                : in.at(i, std::clamp(j + d, 0, h - 1)));
                    }
                    out.at(i, j) = s;
                }
            }
        },
        8);
    return out;
}

/// Convolves rows with `kx`, then columns with `ky`.
Plane separable(const Plane& in, const std::vector<float>& kx, const std::vector<float>& ky,
                int threads) {
    return convolve(convolve(in, kx, true, threads), ky, false, threads);
}

// sRGB's primaries and D65 white (IEC 61966-2-1), linear RGB <-> CIE XYZ.
constexpr float kRgbToXyz[3][3] = {
    {10135552.0f / 24577794.0f, 8788810.0f / 24577794.0f, 4435075.0f / 24577794.0f},
    {2613072.0f / 12288897.0f, 8788810.0f / 12288897.0f, 887015.0f / 12288897.0f},
    {1425312.0f / 73733382.0f, 8788810.0f / 73733382.0f, 70074185.0f / 73733382.0f}};
constexpr float kXyzToRgb[3][3] = {{3.241003275f, -1.537398934f, -0.498615861f},
                                   {-0.969224334f, 1.875930071f, 0.041554224f},
                                   {0.055639423f, -0.204011202f, 1.057148933f}};
constexpr float kWhite[3] = {0.950428545f, 1.0f, 1.088900371f};  // D65's XYZ

vec3 mul(const float m[3][3], vec3 v) {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

/// YCxCz (Edge and Taylor's linearised CIELAB): the opponent space the filters act in.
vec3 rgb_to_ycxcz(vec3 rgb) {
    vec3 xyz = mul(kRgbToXyz, rgb);
    vec3 n(xyz.x / kWhite[0], xyz.y / kWhite[1], xyz.z / kWhite[2]);
    return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

vec3 ycxcz_to_rgb(vec3 c) {
    float y = (c.x + 16.0f) / 116.0f;
    vec3 xyz((y + c.y / 500.0f) * kWhite[0], y * kWhite[1], (y - c.z / 200.0f) * kWhite[2]);
    return mul(kXyzToRgb, xyz);
}

/// CIELAB with Hunt's adjustment: chroma scaled by 0.01 L, as colourfulness falls with
/// luminance.
vec3 rgb_to_hunt_lab(vec3 rgb) {
    vec3 xyz = mul(kRgbToXyz, rgb);
    constexpr float delta = 6.0f / 29.0f;
    auto f = [&](float t) {
        return t > delta * delta * delta ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
    };
    float fx = f(xyz.x / kWhite[0]), fy = f(xyz.y / kWhite[1]), fz = f(xyz.z / kWhite[2]);
    float L = 116.0f * fy - 16.0f;
    return {L, 0.01f * L * 500.0f * (fx - fy), 0.01f * L * 200.0f * (fy - fz)};
}

/// HyAB (Abasi et al. 2020): city-block in lightness, Euclidean in chroma.
float hyab(vec3 a, vec3 b) {
    vec3 d = a - b;
    return std::abs(d.x) + std::sqrt(d.y * d.y + d.z * d.z);
}

constexpr float kQc = 0.7f, kQf = 0.5f;   // the colour and feature exponents
constexpr float kPc = 0.4f, kPt = 0.95f;  // the redistribution's knee

/// The 1D factor of a contrast sensitivity Gaussian a sqrt(π/b) exp(-π² r² / b), r in degrees,
/// sampled at the pixels of [-radius, radius].
std::vector<float> csf_gaussian(float b, int radius, float ppd) {
    std::vector<float> g(2 * radius + 1);
    for (int x = -radius; x <= radius; ++x) {
        float d = static_cast<float>(x) / ppd;
        g[x + radius] = std::exp(-kPi * kPi * d * d / b);
    }
    return g;
}

float sum(const std::vector<float>& v) {
    float s = 0.0f;
    for (float x : v) s += x;
    return s;
}

std::vector<float> scaled(std::vector<float> v, float k) {
    for (float& x : v) x *= k;
    return v;
}

/// One opponent channel filtered by its contrast sensitivity function: one Gaussian (a1, b1)
/// or the sum of two (with a2, b2), normalised to sum 1 over the kernel's square.
Plane csf_filter(const Plane& in, float a1, float b1, float a2, float b2, int radius, float ppd,
                 int threads) {
    std::vector<float> g1 = csf_gaussian(b1, radius, ppd);
    float s1 = sum(g1), w1 = a1 * std::sqrt(kPi / b1);
    if (a2 == 0.0f) return separable(in, scaled(g1, 1.0f / s1), scaled(g1, 1.0f / s1), threads);
    std::vector<float> g2 = csf_gaussian(b2, radius, ppd);
    float s2 = sum(g2), w2 = a2 * std::sqrt(kPi / b2);
    float total = w1 * s1 * s1 + w2 * s2 * s2;
    Plane p1 = separable(in, g1, g1, threads), p2 = separable(in, g2, g2, threads);
    for (size_t k = 0; k < p1.v.size(); ++k) p1.v[k] = (w1 * p1.v[k] + w2 * p2.v[k]) / total;
    return p1;
}

/// The feature detectors' 1D factors: the derivative (edge) or second derivative (point) of
/// a Gaussian across, with its positive weights scaled to sum 1 and its negative ones to -1,
/// and the Gaussian along, scaled to sum 1.
struct FeatureKernels {
    std::vector<float> edge, point, along;
};

FeatureKernels feature_kernels(float ppd) {
    const float sd = 0.5f * 0.082f * ppd;  // half the peak-to-trough width, in pixels
    const int radius = static_cast<int>(std::ceil(3.0f * sd));
    FeatureKernels k;
    for (int x = -radius; x <= radius; ++x) {
        float fx = static_cast<float>(x);
        float g = std::exp(-fx * fx / (2.0f * sd * sd));
        k.along.push_back(g);
        k.edge.push_back(-fx * g);
        k.point.push_back((fx * fx / (sd * sd) - 1.0f) * g);
    }
    for (std::vector<float>* v : {&k.edge, &k.point}) {
        float pos = 0.0f, neg = 0.0f;
        for (float w : *v) (w > 0.0f ? pos : neg) += w;
        for (float& w : *v) w = w > 0.0f ? w / pos : w < 0.0f ? w / -neg : 0.0f;
    }
    k.along = scaled(k.along, 1.0f / sum(k.along));
    return k;
}

/// Per pixel, the magnitudes of the edge and point responses of the achromatic plane.
struct Features {
    Plane edge, point;
};

Features features(const Plane& y, const FeatureKernels& k, int threads) {
    Plane ex = separable(y, k.edge, k.along, threads), ey = separable(y, k.along, k.edge, threads);
    Plane px = separable(y, k.point, k.along, threads),
          py = separable(y, k.along, k.point, threads);
    for (size_t i = 0; i < ex.v.size(); ++i) {
        ex.v[i] = std::hypot(ex.v[i], ey.v[i]);
        px.v[i] = std::hypot(px.v[i], py.v[i]);
    }
    return {std::move(ex), std::move(px)};
}

/// The opponent planes of an image whose pixels are clipped to [0, 1].
std::array<Plane, 3> opponent(const Image& image) {
    std::array<Plane, 3> p = {Plane(image.width, image.height), Plane(image.width, image.height),
                              Plane(image.width, image.height)};
    for (size_t k = 0; k < image.pixels.size(); ++k) {
        vec3 c = glm::clamp(vec3(image.pixels[k]), vec3(0.0f), vec3(1.0f));
        if (!is_finite(c)) c = vec3(0.0f);
        vec3 o = rgb_to_ycxcz(c);
        for (int ch = 0; ch < 3; ++ch) p[ch].v[k] = o[ch];
    }
    return p;
}

/// The colour pipeline's Hunt-adjusted CIELAB of each filtered pixel.
std::vector<vec3> filtered_lab(const std::array<Plane, 3>& o, float ppd, int threads) {
    // The kernels' half-width covers three standard deviations of the widest CSF Gaussian
    // (b = 0.04, the blue-yellow channel's first).
    const int radius =
        static_cast<int>(std::ceil(3.0f * std::sqrt(0.04f / (2.0f * kPi * kPi)) * ppd));
    Plane a = csf_filter(o[0], 1.0f, 0.0047f, 0.0f, 0.0f, radius, ppd, threads);
    Plane rg = csf_filter(o[1], 1.0f, 0.0053f, 0.0f, 0.0f, radius, ppd, threads);
    Plane by = csf_filter(o[2], 34.1f, 0.04f, 13.5f, 0.025f, radius, ppd, threads);
    std::vector<vec3> lab(a.v.size());
    for (size_t k = 0; k < lab.size(); ++k) {
        vec3 rgb = glm::clamp(ycxcz_to_rgb({a.v[k], rg.v[k], by.v[k]}), vec3(0.0f), vec3(1.0f));
        lab[k] = rgb_to_hunt_lab(rgb);
    }
    return lab;
}

}  // namespace

FlipMap flip_ldr(const Image& reference, const Image& test, float ppd, int threads) {
    FlipMap map;
    map.width = reference.width;
    map.height = reference.height;
    std::array<Plane, 3> ro = opponent(reference), to = opponent(test);
    std::vector<vec3> rlab = filtered_lab(ro, ppd, threads), tlab = filtered_lab(to, ppd, threads);
    // The achromatic plane, normalised: (Y' + 16) / 116 = Y / Y_white.
    for (Plane* y : {&ro[0], &to[0]}) {
        for (float& v : y->v) v = (v + 16.0f) / 116.0f;
    }
    FeatureKernels kernels = feature_kernels(ppd);
    Features rf = features(ro[0], kernels, threads), tf = features(to[0], kernels, threads);

    const float cmax = std::pow(hyab(rgb_to_hunt_lab({0, 1, 0}), rgb_to_hunt_lab({0, 0, 1})), kQc);
    const float pccmax = kPc * cmax;
    map.error.resize(rlab.size());
    double total = 0.0;
    for (size_t k = 0; k < rlab.size(); ++k) {
        float c = std::pow(hyab(rlab[k], tlab[k]), kQc);
        float color =
            c < pccmax ? kPt / pccmax * c : kPt + (c - pccmax) / (cmax - pccmax) * (1 - kPt);
        float f = std::max(std::abs(rf.edge.v[k] - tf.edge.v[k]),
                           std::abs(rf.point.v[k] - tf.point.v[k]));
        float feature = std::pow(f / std::sqrt(2.0f), kQf);
        map.error[k] = std::pow(color, 1.0f - feature);
        total += map.error[k];
    }
    map.mean = map.error.empty() ? 0.0 : total / static_cast<double>(map.error.size());
    return map;
}

namespace {

// Narkowicz's fit of the ACES filmic curve with its 0.6 pre-exposure folded in:
// y = (k0 x² + k1 x) / (k3 x² + k4 x + k5), clipped to [0, 1].
constexpr float kAces[6] = {0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f,
                            0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f};

float aces(float x) {
    float num = kAces[0] * x * x + kAces[1] * x + kAces[2];
    float den = kAces[3] * x * x + kAces[4] * x + kAces[5];
    if (std::isinf(den)) return 1.0f;
    return std::clamp(num / den, 0.0f, 1.0f);
}

/// The input x at which the tone curve reaches t (the larger root of the quadratic).
float aces_inverse(float t) {
    float c0 = (kAces[1] - kAces[4] * t) / (kAces[0] - kAces[3] * t);
    float c1 = (kAces[2] - kAces[5] * t) / (kAces[0] - kAces[3] * t);
    return -0.5f * c0 + std::sqrt(0.25f * c0 * c0 - c1);
}

Image tone_mapped(const Image& image, float exposure) {
    Image out(image.width, image.height);
    const float scale = std::exp2(exposure);
    for (size_t k = 0; k < image.pixels.size(); ++k) {
        Color c = glm::max(image.pixels[k], Color(0.0f));
        if (!is_finite(c)) c = Color(0.0f);
        out.pixels[k] = Color(aces(scale * c.r), aces(scale * c.g), aces(scale * c.b));
    }
    return out;
}

}  // namespace

std::vector<float> flip_hdr_exposures(const Image& reference) {
    // The start exposure maps the brightest luminance, the stop exposure the median, to 0.85
    // of the display's range (the paper's t_max = t_min = 0.85).
    std::vector<float> y;
    y.reserve(reference.pixels.size());
    float y_max = 0.0f;
    for (const Color& c : reference.pixels) {
        float v = is_finite(c) ? luminance(glm::max(c, Color(0.0f))) : 0.0f;  // Rec. 709
        y.push_back(v);
        y_max = std::max(y_max, v);
    }
    if (y.empty() || y_max <= 0.0f) return {0.0f, 0.0f};
    auto mid = y.begin() + static_cast<std::ptrdiff_t>(y.size() / 2);
    std::nth_element(y.begin(), mid, y.end());
    // A median of 0 (a black background) would put the stop exposure at infinity.
    const float y_median = std::max(*mid, std::numeric_limits<float>::epsilon());
    const float x = aces_inverse(0.85f);
    const float start = std::log2(x / y_max), stop = std::log2(x / y_median);
    const int count = std::max(2, static_cast<int>(std::ceil(stop - start)));
    std::vector<float> exposures(count);
    for (int k = 0; k < count; ++k)
        exposures[k] =
            start + static_cast<float>(k) * (stop - start) / static_cast<float>(count - 1);
    return exposures;
}

FlipMap flip_hdr(const Image& reference, const Image& test, float ppd, int threads) {
    FlipMap map;
    map.width = reference.width;
    map.height = reference.height;
    map.error.assign(reference.pixels.size(), 0.0f);
    for (float exposure : flip_hdr_exposures(reference)) {
        FlipMap ldr =
            flip_ldr(tone_mapped(reference, exposure), tone_mapped(test, exposure), ppd, threads);
        for (size_t k = 0; k < map.error.size(); ++k)
            map.error[k] = std::max(map.error[k], ldr.error[k]);
    }
    double total = 0.0;
    for (float e : map.error) total += e;
    map.mean = map.error.empty() ? 0.0 : total / static_cast<double>(map.error.size());
    return map;
}

}  // namespace svetlo
