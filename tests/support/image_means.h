// Means over blocks of an image, for the tests that compare renders with closed forms.
#pragma once

#include "svetlo/core/image.h"

namespace svetlo {

/// Mean of one channel over a block of pixels [x0, x1) x [y0, y1).
inline double mean(const Image& im, int x0, int y0, int x1, int y1, int c = 0) {
    double s = 0.0;
    for (int j = y0; j < y1; ++j)
        for (int i = x0; i < x1; ++i) s += im.at(i, j)[c];
    return s / ((x1 - x0) * (y1 - y0));
}
/// Mean of one channel over the whole image.
inline double mean(const Image& im, int c = 0) { return mean(im, 0, 0, im.width, im.height, c); }

}  // namespace svetlo
