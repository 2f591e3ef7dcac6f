// What the film integrates radiance against: three response functions on the 1-nm grid of
// 360-830 nm. The CIE 1931 standard observer (spectral/cie.h) is one; a camera's spectral
// sensitivities (--sensor FILE.csv, spectral/sensor.h) are another, giving raw camera RGB.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "spectral/sampled.h"

namespace spt {

/// Three tristimulus values: X, Y, Z for the CIE observer, a camera's raw r, g, b for a sensor.
struct Xyz {
    double x = 0, y = 0, z = 0;
};

class Observer {
public:
    /// rows[i] = the three responses at 360 + i nm, i = 0..470 (fourth lane ignored). Throws
    /// std::invalid_argument on another row count or a second response with zero integral.
    Observer(std::string name, const std::vector<Float4>& rows);

    /// "CIE 1931 2 degree" or the sensor's file: for messages and file metadata.
    const std::string& name() const { return m_name; }

    /// The responses at λ (nm), linear between the 1-nm table entries, 0 outside 360–830 nm.
    Xyz cmf(float lambda_nm) const {
        const float x = lambda_nm - kLambdaMin;
        if (!(x >= 0.f) || x > m_last) return {};
        const int i = std::min(static_cast<int>(x), static_cast<int>(m_last) - 1);
        const Float4 c = lerp_rows(x - static_cast<float>(i), i);
        return {c[0], c[1], c[2]};
    }
    /// ∫ of the second response (ȳ) over the interpolated table: the normaliser that makes a
    /// constant spectrum of 1 give Y = 1 (for a sensor: green = 1).
    double y_integral() const { return m_y_integral; }

    /// Monte Carlo estimate for one path: (1/K) Σ L(λk)·cmf(λk)/pdf(λk) / ∫ȳ.
    /// Wavelengths with pdf 0 (terminated companions) contribute nothing.
    /// The four wavelengths' look-ups are done together and each table row holds x̄ȳz̄ (one
    /// load per entry instead of three); every lane rounds as the scalar code would (cmf(),
    /// then a double multiply-add per component in wavelength order), so the sums are the same
    /// bits as a plain loop over the wavelengths. Always inlined: the film calls it once per
    /// path, and once the path loop grew GCC made it an out-of-line call.
    [[gnu::always_inline]] Xyz to_xyz(const SampledSpectrum& L, const SampledWavelengths& w) const {
        Float4 lambda, pdf;
        std::memcpy(&lambda, w.lambda.data(), sizeof lambda);
        std::memcpy(&pdf, w.pdf.data(), sizeof pdf);
        const Float4 x = lambda - kLambdaMin;
        const Int4 inside = (x >= 0.f) & (x <= m_last);  // false for NaN, like cmf()
        const Int4 i = inside & min(to_int4(x), splat4(static_cast<std::int32_t>(m_last) - 1));
        const Float4 t = x - to_float4(i);
        // L/pdf in double; lanes of pdf 0 get weight 0 (adding +0 leaves a sum unchanged).
        const Float4 radiance = L.lanes();
        const Double2 pdf01 = low_to_double2(pdf), pdf23 = high_to_double2(pdf);
        const Double2 w01 = pdf01 != 0.0 ? low_to_double2(radiance) / pdf01 : Double2{};
        const Double2 w23 = pdf23 != 0.0 ? high_to_double2(radiance) / pdf23 : Double2{};
        const double weight[kLambdaCount] = {w01[0], w01[1], w23[0], w23[1]};
        Double2 xy{}, z{};  // z̄ in lane 0 (lane 1 sums the padding zeros)
        for (int k = 0; k < kLambdaCount; ++k) {
            const Float4 c = inside[k] ? lerp_rows(t[k], i[k]) : Float4{};
            xy += low_to_double2(c) * weight[k];
            z += high_to_double2(c) * weight[k];
        }
        const double norm = 1.0 / (kLambdaCount * m_y_integral);
        return {xy[0] * norm, xy[1] * norm, z[0] * norm};
    }

    /// A hash of the response table (FNV-1a of its floats): checkpoints of a sensor render
    /// resume only with the same curves.
    std::uint64_t fingerprint() const;

    /// Entries of the 1-nm table (471: 360, 361, ... 830 nm).
    static constexpr int kRows = 471;

private:
    static Int4 min(Int4 a, Int4 b) { return a < b ? a : b; }
    /// Row i and i + 1 blended with weight t: lerp() on each of x̄, ȳ, z̄ (and the padding).
    Float4 lerp_rows(float t, int i) const { return (1.f - t) * m_rows[i] + t * m_rows[i + 1]; }
    std::string m_name;
    std::vector<Float4> m_rows;  ///< x̄, ȳ, z̄, 0 at 360, 361, ... 830 nm
    float m_last = 0;            ///< index of the last entry (470)
    double m_y_integral = 0;
};

}  // namespace spt
