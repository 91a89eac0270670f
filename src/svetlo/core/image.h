// A float RGB image, row-major from the top-left pixel, and the conversions between linear
// values and 8-bit sRGB.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "svetlo/core/math.h"

namespace svetlo {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<Color> pixels;  // width * height, pixel (i, j) at j * width + i

    Image() = default;
    Image(int w, int h, Color fill = Color(0.0f))
        : width(w), height(h), pixels(static_cast<size_t>(w) * static_cast<size_t>(h), fill) {}

    Color& at(int i, int j) { return pixels[static_cast<size_t>(j) * width + i]; }
    const Color& at(int i, int j) const { return pixels[static_cast<size_t>(j) * width + i]; }
};

/// sRGB transfer function (IEC 61966-2-1), both directions, on [0, 1].
float srgb_to_linear(float v);
float linear_to_srgb(float v);
/// Linear value in [0, 1] (clipped) to an 8-bit sRGB code.
unsigned char linear_to_srgb8(float v);

/// linear_to_srgb8 without a power per call, the same code for every float: the codes step up
/// at 255 values, found once from linear_to_srgb8 itself (bisection on the floats, which it
/// maps in order). A table gives the code at the start of each of 4096 equal cells of [0, 1];
/// no cell holds two steps (the steepest slope of the curve, 12.92 x 255 codes per unit at 0,
/// is 0.8 codes a cell), so one comparison with the next step finishes. Writing 8-bit images
/// uses it. No branch: the value is clipped first (NaN to 0), the cell of 1 holds 255, and
/// the step past the last is infinite.
class Srgb8Encoder {
public:
    Srgb8Encoder();
    unsigned char operator()(float v) const {
        const float c = std::max(0.0f, std::min(v, 1.0f));  // NaN to 0 (min keeps it, max drops it)
        const unsigned k = first_[static_cast<unsigned>(c * kCells)];  // exact: kCells is 2^12
        return static_cast<unsigned char>(k + (steps_[k] <= c ? 1u : 0u));
    }

private:
    static constexpr unsigned kCells = 4096;
    float steps_[256];                 // steps_[k - 1]: the least float whose code is k; then inf
    unsigned char first_[kCells + 1];  // the code of c / kCells
};

/// The w x h pixels of `image` whose top-left corner is (x0, y0), all inside it.
Image crop_image(const Image& image, int x0, int y0, int w, int h);

/// A radiance image as an 8-bit PNG holds it (scaled by `exposure`, clipped, sRGB-encoded),
/// decoded back to linear values: what a viewer of the PNG sees.
Image as_8bit_srgb(const Image& image, float exposure);

}  // namespace svetlo
