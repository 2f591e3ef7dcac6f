// Analytic spectral functions that materials, emitters and indices of refraction are built from.
// A source is evaluated exactly at any wavelength; Spectrum bins it for speed.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace spt {

struct SpectrumSource {
    enum class Kind {
        Constant,         ///< value
        Gaussian,         ///< offset + scale·exp(−((λ−center)/width)²)
        Sigmoid,          ///< offset + scale/(1 + exp(−(λ−center)/width))  (logistic step)
        Blackbody,        ///< scale·B(λ, T)/B(normalize_nm, T), B = Planck spectral radiance
        PiecewiseLinear,  ///< linear between table points, end values held outside
        Cauchy,           ///< A + B/λ² + C/λ⁴, λ in µm
        Sellmeier,        ///< sqrt(1 + Σ Bᵢλ²/(λ² − Cᵢ)), λ in µm, Cᵢ in µm²
        RgbSigmoid,       ///< scale·s(c0·t² + c1·t + c2), s(x) = ½ + x/(2√(1+x²)), t = (λ−360)/470; see rgb_to_spectrum
        Product,          ///< scale·Π factors(λ)
    };
    Kind kind = Kind::Constant;
    double p[6] = {0, 0, 0, 0, 0, 0};                ///< parameters, meaning set by kind
    std::vector<std::pair<double, double>> table;  ///< PiecewiseLinear (λ nm, value), sorted
    std::vector<SpectrumSource> factors;           ///< Product (at least one)

    static SpectrumSource constant(double value);
    static SpectrumSource gaussian(double center_nm, double width_nm, double scale, double offset = 0);
    static SpectrumSource sigmoid(double center_nm, double width_nm, double scale, double offset = 0);
    static SpectrumSource blackbody(double kelvin, double scale = 1, double normalize_nm = 560);
    static SpectrumSource piecewise_linear(std::vector<std::pair<double, double>> points);
    static SpectrumSource cauchy(double a, double b_um2, double c_um4 = 0);
    static SpectrumSource sellmeier(double b1, double b2, double b3, double c1, double c2, double c3);
    static SpectrumSource rgb_sigmoid(double c0, double c1, double c2, double scale = 1);
    static SpectrumSource product(std::vector<SpectrumSource> factors, double scale = 1);

    /// The same kind, parameters, table and factors (so the same function of λ).
    bool operator==(const SpectrumSource&) const = default;

    /// Exact value at λ (nm).
    double eval(double lambda_nm) const;
    /// True when the value does not depend on λ (no dispersion, no binning error).
    bool is_constant() const;
    /// Short human-readable description, for messages.
    std::string describe() const;
};

/// Planck's law: spectral radiance of a blackbody (W·sr⁻¹·m⁻³) at λ (nm), temperature T (K).
double planck(double lambda_nm, double kelvin);

}  // namespace spt
