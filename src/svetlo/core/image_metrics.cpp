#include "svetlo/core/image_metrics.h"

#include <algorithm>
#include <cmath>

namespace svetlo {

namespace {

/// The squared and absolute error of one channel, and the relative squared error.
struct ChannelError {
    double abs, sq, rel;
};

ChannelError channel_error(float a, float b) {
    double x = std::isfinite(a) ? a : 0.0, y = std::isfinite(b) ? b : 0.0;
    double d = x - y;
    return {std::abs(d), d * d, d * d / ((y + 0.01) * (y + 0.01))};
}

}  // namespace

PixelMetrics pixel_metrics(const Image& test, const Image& reference) {
    PixelMetrics m;
    const size_t n = std::min(test.pixels.size(), reference.pixels.size());
    if (n == 0) return m;
    double abs = 0.0, sq = 0.0, rel = 0.0;
    for (size_t k = 0; k < n; ++k) {
        for (int c = 0; c < 3; ++c) {
            ChannelError e = channel_error(test.pixels[k][c], reference.pixels[k][c]);
            abs += e.abs;
            sq += e.sq;
            rel += e.rel;
        }
    }
    const double count = 3.0 * static_cast<double>(n);
    m.mae = abs / count;
    m.rmse = std::sqrt(sq / count);
    m.relmse = rel / count;
    return m;
}

std::vector<float> pixel_errors(const Image& test, const Image& reference,
                                const std::string& name) {
    const size_t n = std::min(test.pixels.size(), reference.pixels.size());
    std::vector<float> out(n);
    for (size_t k = 0; k < n; ++k) {
        double abs = 0.0, sq = 0.0, rel = 0.0;
        for (int c = 0; c < 3; ++c) {
            ChannelError e = channel_error(test.pixels[k][c], reference.pixels[k][c]);
            abs += e.abs;
            sq += e.sq;
            rel += e.rel;
        }
        out[k] = static_cast<float>(name == "mae"    ? abs / 3.0
                                    : name == "rmse" ? std::sqrt(sq / 3.0)
                                                     : rel / 3.0);
    }
    return out;
}

Color magma(float t) {
    // matplotlib's magma at t = 0, 0.2, ..., 1 (its display codes / 255), linearly between.
    static constexpr float stops[6][3] = {{0x00, 0x00, 0x04}, {0x3b, 0x0f, 0x70},
                                          {0x8c, 0x29, 0x81}, {0xde, 0x49, 0x68},
                                          {0xfe, 0x9f, 0x6d}, {0xfc, 0xfd, 0xbf}};
    t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) : 1.0f;
    float x = t * 5.0f;
    int k = std::min(static_cast<int>(x), 4);
    float f = x - static_cast<float>(k);
    Color c;
    for (int ch = 0; ch < 3; ++ch)
        c[ch] = ((1.0f - f) * stops[k][ch] + f * stops[k + 1][ch]) / 255.0f;
    return c;
}

Image false_color(const std::vector<float>& errors, int width, int height, float top) {
    Image out(width, height);
    const float scale = top > 0.0f ? 1.0f / top : 0.0f;
    for (size_t k = 0; k < out.pixels.size() && k < errors.size(); ++k)
        out.pixels[k] = magma(errors[k] * scale);
    return out;
}

}  // namespace svetlo
