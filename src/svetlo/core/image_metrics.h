// The numbers that say how far an image is from a reference (docs/metrics.md), over every
// pixel and channel of linear RGB:
//   mae    mean |a - b|
//   rmse   sqrt(mean (a - b)²)
//   relmse mean (a - b)² / (b + 0.01)², b the reference: the relative error that weighs dark
//          and bright regions alike (the 0.01 keeps black pixels finite)
// and the false colour that shows a per-pixel error.
#pragma once

#include <string>
#include <vector>

#include "svetlo/core/image.h"

namespace svetlo {

struct PixelMetrics {
    double mae = 0.0, rmse = 0.0, relmse = 0.0;
};

/// The metrics of `test` against `reference` (the same size). A value that is not finite
/// in either image counts as 0.
PixelMetrics pixel_metrics(const Image& test, const Image& reference);

/// Per pixel, the metric `name` (mae, rmse or relmse) of the pixel's three channels: the
/// error image of `svetlo diff`. rmse's per pixel is its squared error's root.
std::vector<float> pixel_errors(const Image& test, const Image& reference, const std::string& name);

/// An error in [0, 1] as a colour of the magma ramp (black, purple, red, orange, pale
/// yellow), as display values in [0, 1] (written to PNG as they are).
Color magma(float t);

/// Per-pixel errors as a false-colour image, `top` mapping to the end of the ramp.
Image false_color(const std::vector<float>& errors, int width, int height, float top);

}  // namespace svetlo
