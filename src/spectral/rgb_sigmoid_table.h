// RGB → rgb_sigmoid coefficients fast enough for every texel of an HDR image (environment
// maps hold millions of distinct colours; rgb_to_spectrum's exact fit costs tens of µs each).
// The spectrum of an RGB illuminant is scale · s(c0·t² + c1·t + c2) · D65(λ) with D65
// normalised to luminance 1 (rgb_texels.h): the same rule as emission texels.
#pragma once
#include <array>
#include <cmath>

namespace spt {

/// The three coefficients of SpectrumSource::rgb_sigmoid (t = (λ − 360 nm)/470 nm).
struct SigmoidCoefficients {
    float c0 = 0, c1 = 0, c2 = 0;

    float eval(float lambda_nm) const {
        const float t = (lambda_nm - 360.f) * (1.f / 470.f);
        const float x = (c0 * t + c1) * t + c2;
        return 0.5f + x / (2.f * std::sqrt(1.f + x * x));
    }
};

/// Coefficients whose spectrum, lit by D65, has the XYZ of linear sRGB `rgb` (each component
/// in [0, 1]; finite). Thread-safe.
SigmoidCoefficients rgb_sigmoid_coefficients(const std::array<float, 3>& rgb);

/// An RGB illuminant (components ≥ 0, finite): scale · s(λ) · D65 of luminance 1 has the XYZ
/// of `rgb` (scale = 2·max component, so the fitted colour stays in [0, ½]).
struct RgbIlluminant {
    SigmoidCoefficients shape;
    float scale = 0;
};
RgbIlluminant rgb_illuminant(const std::array<float, 3>& rgb);

}  // namespace spt
