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

/// linear_to_srgb8 by a search among the 255 values where its code steps up, found once from
/// linear_to_srgb8 itself (bisection on the floats, which it maps in order): the same code for
/// every float, without a power per call. Writing 8-bit images uses it.
class Srgb8Encoder {
public:
    Srgb8Encoder();
    unsigned char operator()(float v) const {
        if (!(v > 0.0f)) return 0;  // also NaN
        unsigned k = 0;             // the number of steps at or below v
        for (unsigned half = 128; half > 0; half /= 2)
            if (k + half <= 255 && steps_[k + half - 1] <= v) k += half;
        return static_cast<unsigned char>(k);
    }

private:
    float steps_[255];  // steps_[k - 1]: the least float whose code is k
};

/// The w x h pixels of `image` whose top-left corner is (x0, y0), all inside it.
Image crop_image(const Image& image, int x0, int y0, int w, int h);

/// A radiance image as an 8-bit PNG holds it (scaled by `exposure`, clipped, sRGB-encoded),
/// decoded back to linear values: what a viewer of the PNG sees.
Image as_8bit_srgb(const Image& image, float exposure);

}  // namespace svetlo
