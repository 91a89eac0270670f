// Wavelengths for dispersion. The path tracer transports RGB; a path that meets a dispersive
// dielectric picks one wavelength there and carries it on (docs/path.md, "Dispersion"):
//
//   L_rgb = E_lambda[ w(lambda) L(lambda) ],  lambda uniform on [380, 780] nm,
//
// where w(lambda) is the sRGB colour of a unit spectral line, through the CIE 1931 matching
// functions (the multi-lobe fit of Wyman, Sloan and Shirley, JCGT 2(2), 2013) and the XYZ to
// linear sRGB matrix (IEC 61966-2-1), clipped at 0 and scaled per channel so that
// E[w(lambda)] = (1, 1, 1): light that does not disperse keeps its RGB colour exactly, and an
// equal-energy spectrum is white. The clipping leaves the spectral colours outside sRGB's
// gamut at its edge instead of letting them go negative.
#pragma once

#include <array>

#include "svetlo/core/math.h"

namespace svetlo {

inline constexpr float kLambdaMin = 380.0f, kLambdaMax = 780.0f;  // nm

/// The refractive index at `lambda_nm` of a glass with index `ior_d` at the helium d line
/// (587.6 nm) and Abbe number `abbe` = (n_d - 1) / (n_F - n_C), by Cauchy's n = A + B /
/// lambda^2 through those two numbers (F = 486.1 nm, C = 656.3 nm).
inline float cauchy_ior(float ior_d, float abbe, float lambda_nm) {
    constexpr float kD = 587.6f, kF = 486.1f, kC = 656.3f;
    const float b = (ior_d - 1.0f) / (abbe * (1.0f / (kF * kF) - 1.0f / (kC * kC)));
    return ior_d + b * (1.0f / (lambda_nm * lambda_nm) - 1.0f / (kD * kD));
}

/// w(lambda) of the header, tabulated at 1 nm and interpolated linearly.
class WavelengthWeights {
public:
    WavelengthWeights();
    /// lambda = 380 + 400 u nm for u in [0, 1).
    static float lambda_of(float u) { return kLambdaMin + (kLambdaMax - kLambdaMin) * u; }
    Color weight(float lambda_nm) const;

private:
    static constexpr int kSize = 401;  // 380..780 nm
    std::array<Color, kSize> table_;
};

/// The CIE 1931 2-degree matching functions (x, y, z) at lambda (nm), by the multi-lobe fit.
vec3 cie_xyz(float lambda_nm);

}  // namespace svetlo
