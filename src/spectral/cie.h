// CIE 1931 2° colour matching functions (from spectra/cie_1931_2deg.csv) and the conversion
// of sampled radiance to XYZ, normalised so that a constant spectrum of 1 gives Y = 1.
#pragma once
#include <vector>

#include "spectral/sampled.h"

namespace spt {

struct Xyz {
    double x = 0, y = 0, z = 0;
};

class Cie1931 {
public:
    static const Cie1931& get();

    /// x̄, ȳ, z̄ at λ (nm), linear between the 1-nm table entries, 0 outside 360–830 nm.
    Xyz cmf(float lambda_nm) const {
        const float x = lambda_nm - kLambdaMin;
        if (!(x >= 0.f) || x > m_last) return {};
        const int i = std::min(static_cast<int>(x), static_cast<int>(m_last) - 1);
        const float t = x - static_cast<float>(i);
        const float* a = &m_xyz[3 * i];
        return {lerp(t, a[0], a[3]), lerp(t, a[1], a[4]), lerp(t, a[2], a[5])};
    }

    /// ∫ȳ dλ of the interpolated table (the normaliser that makes constant 1 give Y = 1).
    double y_integral() const { return m_y_integral; }

    /// Monte Carlo estimate of XYZ for one path: (1/K) Σ L(λk)·cmf(λk)/pdf(λk) / ∫ȳ.
    /// Wavelengths with pdf 0 (terminated companions) contribute nothing.
    Xyz to_xyz(const SampledSpectrum& L, const SampledWavelengths& w) const {
        Xyz sum;
        for (int i = 0; i < kLambdaCount; ++i) {
            if (w.pdf[i] == 0.f) continue;
            const Xyz c = cmf(w.lambda[i]);
            const double weight = static_cast<double>(L[i]) / w.pdf[i];
            sum.x += c.x * weight, sum.y += c.y * weight, sum.z += c.z * weight;
        }
        const double norm = 1.0 / (kLambdaCount * m_y_integral);
        return {sum.x * norm, sum.y * norm, sum.z * norm};
    }

private:
    Cie1931();
    std::vector<float> m_xyz;  ///< interleaved x̄ȳz̄ at 360, 361, ... 830 nm
    float m_last = 0;          ///< index of the last entry (470)
    double m_y_integral = 0;
};

}  // namespace spt
