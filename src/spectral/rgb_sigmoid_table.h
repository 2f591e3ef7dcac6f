// RGB → rgb_sigmoid coefficients fast enough for every texel of an HDR image (environment
// maps hold millions of distinct colours; rgb_to_spectrum's exact fit costs tens of µs each).
// The spectrum of an RGB illuminant is scale · s(c0·t² + c1·t + c2) · D65(λ) with D65
// normalised to luminance 1 (rgb_texels.h): the same rule as emission texels.
//
// A coefficient table in the scheme of Jakob & Hanika 2019, as pbrt-v4's RGBToSpectrumTable
// uses it: for each choice of the largest component, z = that component and the other two
// divided by z index 3 × 32 × 32 × 32 nodes of coefficients (1.2 MB of floats; node layout and
// spacing in rgb_sigmoid_table_data.h), interpolated trilinearly; greys get constant spectra directly.
// The nodes are fitted with rgb_to_spectrum's own fit (CIELAB under D65, 1-nm sums), each from
// a neighbouring node's solution, by make_rgb_sigmoid_table, which CMake builds optimised and
// without sanitizers in every build type and runs at build time: about 4 s of CPU, plus about
// 5 s to compile its 4.8 MB output. Fitted on first use instead, the same work would cost
// seconds at start-up, far beyond the 0.1 s that would make that worth it.
//
// Against the exact colour (tests/test_rgb_sigmoid_table.cpp): CIEDE2000 max 0.27, mean 0.04
// over a 25³ grid of [0, 1]³ and 20 000 random colours; illuminants (which only read the plane
// z = ½, a node) max 0.17, mean 0.02. A lookup is lock-free (the table is constant data) and
// costs about 30 ns for the texels of a smooth image in scan order, 120 ns for colours in
// random order (cache misses in the table), measured on a busy shared machine.
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
