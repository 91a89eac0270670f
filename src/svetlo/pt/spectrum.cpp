#include "svetlo/pt/spectrum.h"

namespace svetlo {

namespace {

/// A Gaussian lobe with different widths on either side of its peak (nm).
float lobe(float lambda, float mu, float sigma_below, float sigma_above) {
    float t = (lambda - mu) / (lambda < mu ? sigma_below : sigma_above);
    return std::exp(-0.5f * t * t);
}

}  // namespace

vec3 cie_xyz(float l) {
    // Wyman, Sloan and Shirley 2013, table 1 (the multi-lobe fit).
    float x = 1.056f * lobe(l, 599.8f, 37.9f, 31.0f) + 0.362f * lobe(l, 442.0f, 16.0f, 26.7f) -
              0.065f * lobe(l, 501.1f, 20.4f, 26.2f);
    float y = 0.821f * lobe(l, 568.8f, 46.9f, 40.5f) + 0.286f * lobe(l, 530.9f, 16.3f, 31.1f);
    float z = 1.217f * lobe(l, 437.0f, 11.8f, 36.0f) + 0.681f * lobe(l, 459.0f, 26.0f, 13.8f);
    return vec3(x, y, z);
}

WavelengthWeights::WavelengthWeights() {
    glm::dvec3 sum(0.0);
    for (int k = 0; k < kSize; ++k) {
        vec3 c = cie_xyz(kLambdaMin + static_cast<float>(k));
        // XYZ to linear sRGB (D65), IEC 61966-2-1.
        Color rgb(3.2406f * c.x - 1.5372f * c.y - 0.4986f * c.z,
                  -0.9689f * c.x + 1.8758f * c.y + 0.0415f * c.z,
                  0.0557f * c.x - 0.2040f * c.y + 1.0570f * c.z);
        table_[static_cast<size_t>(k)] = glm::max(rgb, Color(0.0f));
        // The trapezoid rule's weights, so that weight() integrates to exactly its mean.
        sum += glm::dvec3(table_[static_cast<size_t>(k)]) * (k == 0 || k == kSize - 1 ? 0.5 : 1.0);
    }
    const glm::dvec3 mean = sum / static_cast<double>(kSize - 1);
    for (Color& c : table_) c = Color(glm::dvec3(c) / mean);
}

Color WavelengthWeights::weight(float lambda_nm) const {
    float x = std::clamp(lambda_nm - kLambdaMin, 0.0f, static_cast<float>(kSize - 1));
    int k = std::min(static_cast<int>(x), kSize - 2);
    float t = x - static_cast<float>(k);
    return glm::mix(table_[static_cast<size_t>(k)], table_[static_cast<size_t>(k) + 1], t);
}

}  // namespace svetlo
