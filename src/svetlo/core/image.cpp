#include "svetlo/core/image.h"

#include <cstdint>
#include <limits>

#include "svetlo/core/bit_cast.h"

namespace svetlo {

float srgb_to_linear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

unsigned char linear_to_srgb8(float v) {
    if (!(v > 0.0f)) return 0;  // also maps NaN to black
    if (v >= 1.0f) return 255;
    return static_cast<unsigned char>(std::lround(linear_to_srgb(v) * 255.0f));
}

Srgb8Encoder::Srgb8Encoder() {
    for (unsigned k = 1; k <= 255; ++k) {
        // The least positive float with code >= k: bisection on the bit patterns of the
        // floats in (0, 1], which are ordered as the floats are.
        uint32_t lo = 0, hi = svetlo::bit_cast<uint32_t>(1.0f);  // code(lo) < k <= code(hi)
        while (hi - lo > 1) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (linear_to_srgb8(svetlo::bit_cast<float>(mid)) >= k) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        steps_[k - 1] = svetlo::bit_cast<float>(hi);
    }
    steps_[255] = std::numeric_limits<float>::infinity();
    for (unsigned c = 0; c <= kCells; ++c) {
        const float start = static_cast<float>(c) / kCells;
        unsigned k = 0;  // the steps at or below the cell's start
        while (k < 255 && steps_[k] <= start) ++k;
        first_[c] = static_cast<unsigned char>(k);
    }
}

Image crop_image(const Image& image, int x0, int y0, int w, int h) {
    Image part(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) part.at(i, j) = image.at(x0 + i, y0 + j);
    return part;
}

Image as_8bit_srgb(const Image& image, float exposure) {
    Image out(image.width, image.height);
    for (size_t k = 0; k < image.pixels.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            out.pixels[k][c] = srgb_to_linear(
                static_cast<float>(linear_to_srgb8(image.pixels[k][c] * exposure)) / 255.0f);
        }
    }
    return out;
}

}  // namespace svetlo
