// The wavelengths a path carries (hero + rotated companions) and spectral values at them.
#pragma once
#include <array>
#include <cmath>
#include <cstring>

#include "core/fast_math.h"
#include "core/math.h"
#include "core/simd.h"

namespace spt {

/// Wavelengths per path: one hero plus three companions (Wilkie et al. 2014).
inline constexpr int kLambdaCount = 4;
/// Range of wavelength sampling and of the film's colour matching functions (nm).
inline constexpr float kLambdaMin = 360.f, kLambdaMax = 830.f;

/// Spectral values at the path's wavelengths (radiance, throughput, reflectance...).
/// Arithmetic works on all four lanes at once (core/simd.h); operator[] reads one lane.
struct SampledSpectrum {
    /// The lanes as one vector, not an array of four floats: GCC splits a small array held in
    /// registers into four scalars (scalar replacement of aggregates) and rebuilds the vector
    /// through memory for each vector operation, four narrow stores and a wide load that
    /// cannot be forwarded (the path's radiance stalled so on its way to the film).
    Float4 v{};

    SampledSpectrum() = default;
    explicit SampledSpectrum(float c) : v(splat4(c)) {}
    explicit SampledSpectrum(Float4 lanes) : v(lanes) {}

    /// One lane, writable (GCC's vector types alias their element type, so the lane is
    /// addressable as a float).
    float& operator[](int i) { return reinterpret_cast<float*>(&v)[i]; }
    float operator[](int i) const { return v[i]; }

    Float4 lanes() const { return v; }
    void set_lanes(Float4 r) { v = r; }

#define SPT_ELEMENTWISE(op)                                                         \
    SampledSpectrum& operator op##=(const SampledSpectrum& b) {                     \
        set_lanes(lanes() op b.lanes());                                            \
        return *this;                                                               \
    }                                                                               \
    SampledSpectrum operator op(const SampledSpectrum& b) const {                   \
        return SampledSpectrum(lanes() op b.lanes());                               \
    }                                                                               \
    SampledSpectrum& operator op##=(float s) {                                      \
        set_lanes(lanes() op splat4(s));                                            \
        return *this;                                                               \
    }                                                                               \
    SampledSpectrum operator op(float s) const {                                    \
        return SampledSpectrum(lanes() op splat4(s));                               \
    }
    SPT_ELEMENTWISE(+)
    SPT_ELEMENTWISE(-)
    SPT_ELEMENTWISE(*)
    SPT_ELEMENTWISE(/)
#undef SPT_ELEMENTWISE

    float max_value() const { return std::max(std::max(v[0], v[1]), std::max(v[2], v[3])); }
    float average() const { return (v[0] + v[1] + v[2] + v[3]) / kLambdaCount; }
    bool is_zero() const { return lane_bits(lanes() == 0.f) == 0xfu; }
};
static_assert(kLambdaCount == 4, "SampledSpectrum maps the wavelengths onto one Float4");

/// Density of visible-wavelength sampling (Radziszewski et al. 2009), exactly normalised on
/// [360, 830] nm and shaped like the eye's sensitivity, so film noise is spread evenly.
inline float visible_wavelength_pdf(float lambda_nm) {
    if (lambda_nm < kLambdaMin || lambda_nm > kLambdaMax) return 0.f;
    const float c = std::cosh(0.0072f * (lambda_nm - 538.f));
    return 0.0039398042f / (c * c);
}

/// Inverse CDF of visible_wavelength_pdf for u in [0, 1), four at a time, returning λ and
/// its pdf together: with y = tanh(0.0072·(538 − λ)), cosh⁻² = 1 − y², so the pdf costs no
/// transcendental, and atanh(y) = ½·log((1 + y)/(1 − y)) needs a single logarithm.
inline void sample_visible_wavelength(Float4 u, Float4& lambda_nm, Float4& pdf) {
    const Float4 y = 0.85691062f - 1.82750197f * u;
    // (1 + y)/(1 − y) lies in [0.0149, 12.97]: inside log_positive's domain.
    const Float4 lambda = 538.f - 69.4444444f * log_positive((1.f + y) / (1.f - y));
    lambda_nm = min4(max4(lambda, splat4(kLambdaMin)), splat4(kLambdaMax));
    pdf = 0.0039398042f * (1.f - y * y);
}
inline void sample_visible_wavelength(float u, float& lambda_nm, float& pdf) {
    Float4 l, p;
    sample_visible_wavelength(splat4(u), l, p);
    lambda_nm = l[0], pdf = p[0];
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
        Float4 ui = u + Float4{0.f, 1.f / kLambdaCount, 2.f / kLambdaCount, 3.f / kLambdaCount};
        ui = ui >= 1.f ? ui - 1.f : ui;
        Float4 l, p;
        sample_visible_wavelength(ui, l, p);
        SampledWavelengths w;
        std::memcpy(w.lambda.data(), &l, sizeof l);
        std::memcpy(w.pdf.data(), &p, sizeof p);
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
