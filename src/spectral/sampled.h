// The wavelengths a path carries (hero + rotated companions) and spectral values at them.
#pragma once
#include <array>
#include <cmath>

#include "core/math.h"

namespace spt {

/// Wavelengths per path: one hero plus three companions (Wilkie et al. 2014).
inline constexpr int kLambdaCount = 4;
/// Range of wavelength sampling and of the film's colour matching functions (nm).
inline constexpr float kLambdaMin = 360.f, kLambdaMax = 830.f;

/// Spectral values at the path's wavelengths (radiance, throughput, reflectance...).
struct SampledSpectrum {
    std::array<float, kLambdaCount> v{};

    SampledSpectrum() = default;
    explicit SampledSpectrum(float c) { v.fill(c); }

    float& operator[](int i) { return v[i]; }
    float operator[](int i) const { return v[i]; }

#define SPT_ELEMENTWISE(op)                                                         \
    SampledSpectrum& operator op##=(const SampledSpectrum& b) {                     \
        for (int i = 0; i < kLambdaCount; ++i) v[i] op## = b.v[i];                  \
        return *this;                                                               \
    }                                                                               \
    SampledSpectrum operator op(const SampledSpectrum& b) const {                   \
        SampledSpectrum r = *this;                                                  \
        return r op## = b;                                                          \
    }                                                                               \
    SampledSpectrum& operator op##=(float s) {                                      \
        for (int i = 0; i < kLambdaCount; ++i) v[i] op## = s;                       \
        return *this;                                                               \
    }                                                                               \
    SampledSpectrum operator op(float s) const {                                    \
        SampledSpectrum r = *this;                                                  \
        return r op## = s;                                                          \
    }
    SPT_ELEMENTWISE(+)
    SPT_ELEMENTWISE(-)
    SPT_ELEMENTWISE(*)
    SPT_ELEMENTWISE(/)
#undef SPT_ELEMENTWISE

    float max_value() const {
        float m = v[0];
        for (int i = 1; i < kLambdaCount; ++i) m = std::max(m, v[i]);
        return m;
    }
    float average() const {
        float s = 0.f;
        for (float x : v) s += x;
        return s / kLambdaCount;
    }
    bool is_zero() const {
        for (float x : v)
            if (x != 0.f) return false;
        return true;
    }
};

/// Density of visible-wavelength sampling (Radziszewski et al. 2009), exactly normalised on
/// [360, 830] nm and shaped like the eye's sensitivity, so film noise is spread evenly.
inline float visible_wavelength_pdf(float lambda_nm) {
    if (lambda_nm < kLambdaMin || lambda_nm > kLambdaMax) return 0.f;
    const float c = std::cosh(0.0072f * (lambda_nm - 538.f));
    return 0.0039398042f / (c * c);
}

/// Inverse CDF of visible_wavelength_pdf for u in [0, 1), returning λ and its pdf together:
/// with y = tanh(0.0072·(538 − λ)), cosh⁻² = 1 − y², so the pdf costs no transcendental, and
/// atanh(y) = ½·log((1 + y)/(1 − y)) needs a single logarithm.
inline void sample_visible_wavelength(float u, float& lambda_nm, float& pdf) {
    const float y = 0.85691062f - 1.82750197f * u;
    const float lambda = 538.f - 69.4444444f * std::log((1.f + y) / (1.f - y));
    lambda_nm = std::clamp(lambda, kLambdaMin, kLambdaMax);
    pdf = 0.0039398042f * (1.f - y * y);
}
inline float sample_visible_wavelength(float u) {
    float lambda, pdf;
    sample_visible_wavelength(u, lambda, pdf);
    return lambda;
}

/// The hero wavelength and its companions, each with the pdf it was sampled with.
/// After terminate_secondary() only the hero carries the path (dispersive refraction).
struct SampledWavelengths {
    std::array<float, kLambdaCount> lambda{};
    std::array<float, kLambdaCount> pdf{};

    /// Hero from u, companions from u + k/K (mod 1) through the same inverse CDF (stratified).
    static SampledWavelengths sample(float u) {
        SampledWavelengths w;
        for (int i = 0; i < kLambdaCount; ++i) {
            float ui = u + static_cast<float>(i) / kLambdaCount;
            if (ui >= 1.f) ui -= 1.f;
            sample_visible_wavelength(ui, w.lambda[i], w.pdf[i]);
        }
        return w;
    }

    /// The film averages over K wavelengths, so the surviving hero's pdf is divided by K
    /// to keep the estimate unbiased while companions contribute nothing (pdf = 0).
    void terminate_secondary() {
        if (secondary_terminated()) return;
        for (int i = 1; i < kLambdaCount; ++i) pdf[i] = 0.f;
        pdf[0] /= kLambdaCount;
    }
    bool secondary_terminated() const { return pdf[1] == 0.f; }
};

}  // namespace spt
