// A float RGB image, row-major from the top-left pixel, and the conversions between linear
// values and 8-bit sRGB.
#pragma once

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
/// uses it.
class Srgb8Encoder {
public:
    Srgb8Encoder();
    unsigned char operator()(float v) const {
        if (!(v > 0.0f)) return 0;  // also NaN
        if (v >= 1.0f) return 255;
        const unsigned k = first_[static_cast<unsigned>(v * kCells)];  // exact: kCells is 2^12
        return static_cast<unsigned char>(k < 255 && steps_[k] <= v ? k + 1 : k);
    }

private:
    static constexpr unsigned kCells = 4096;
    float steps_[255];             // steps_[k - 1]: the least float whose code is k
    unsigned char first_[kCells];  // the code of c / kCells
};

/// The w x h pixels of `image` whose top-left corner is (x0, y0), all inside it.
Image crop_image(const Image& image, int x0, int y0, int w, int h);

/// A radiance image as an 8-bit PNG holds it (scaled by `exposure`, clipped, sRGB-encoded),
/// decoded back to linear values: what a viewer of the PNG sees.
Image as_8bit_srgb(const Image& image, float exposure);

}  // namespace svetlo
