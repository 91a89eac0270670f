// ꟻLIP, the perceptual difference of two images as a viewer flipping between them sees it
// (docs/metrics.md):
//   LDR-ꟻLIP: Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild, "ꟻLIP: A
//   Difference Evaluator for Alternating Images", HPG 2020;
//   HDR-ꟻLIP: Andersson, Nilsson, Shirley and Akenine-Möller, "Visualizing Errors in Rendered
//   High Dynamic Range Images", Eurographics 2021.
// Each pixel's error is in [0, 1]: 0 where the two images cannot be told apart.
#pragma once

#include <vector>

#include "svetlo/core/image.h"

namespace svetlo {

/// Pixels per degree of visual angle of the papers' observer: a 0.7 m wide 3840-pixel
/// monitor seen from 0.7 m, (0.7 m × 3840 / 0.7 m) × π / 180 ≈ 67.02.
inline constexpr float kFlipPixelsPerDegree = 0.7f * 3840.0f / 0.7f * 3.14159265358979f / 180.0f;

/// Per-pixel errors, row-major from the top-left pixel, and their mean.
struct FlipMap {
    int width = 0, height = 0;
    std::vector<float> error;
    double mean = 0.0;
};

/// LDR-ꟻLIP of two images of the same size whose pixels are linear RGB in [0, 1] (an 8-bit
/// sRGB file decoded through the sRGB curve; values outside are clipped).
FlipMap flip_ldr(const Image& reference, const Image& test,
                 float pixels_per_degree = kFlipPixelsPerDegree, int threads = 0);

/// HDR-ꟻLIP of two linear radiance images: LDR-ꟻLIP of both after exposure compensation and
/// the ACES tone curve, at exposures from the reference's brightest pixel to its median,
/// the largest error of each pixel kept. Negative values count as 0.
FlipMap flip_hdr(const Image& reference, const Image& test,
                 float pixels_per_degree = kFlipPixelsPerDegree, int threads = 0);

/// The exposures HDR-ꟻLIP evaluates for `reference` (stops: the image is scaled by 2^e).
std::vector<float> flip_hdr_exposures(const Image& reference);

}  // namespace svetlo
