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

/// The w x h pixels of `image` whose top-left corner is (x0, y0), all inside it.
Image crop_image(const Image& image, int x0, int y0, int w, int h);

/// A radiance image as an 8-bit PNG holds it (scaled by `exposure`, clipped, sRGB-encoded),
/// decoded back to linear values: what a viewer of the PNG sees.
Image as_8bit_srgb(const Image& image, float exposure);

}  // namespace svetlo
