// The Hosek–Wilkie clear-sky model, spectral: the sky dome (Hosek & Wilkie 2012, "An Analytic
// Model for Full Spectral Sky-Dome Radiance", ACM TOG 31(4)) and the solar radiance function
// with limb darkening (Hosek & Wilkie 2013, "Adding a Solar-Radiance Function to the
// Hosek-Wilkie Skylight Model", IEEE CG&A 33(3)). Their fitted datasets (11 channels,
// 320–720 nm every 40 nm; BSD licence, kept in the tables' comments) are
// spectra/hosek_wilkie_{sky,sun}.csv, written by tools/hosek_wilkie_tables.py.
//
// Sky (per channel): the extended Perez formula of the 2012 paper (its eq. 9),
//   F(θ, γ) = (1 + A·e^{B/(cos θ + 0.01)})·(C + D·e^{Eγ} + F·cos²γ + G·χ(H, γ) + I·√cos θ),
//   χ(g, α) = (1 + cos²α)/(1 + g² − 2g·cos α)^{3/2},
// times the channel's radiance scale L_M (eq. 10), θ the zenith angle of the view, γ its
// angle to the sun. Each of the ten numbers is a quintic Bézier curve over x = (η/90°)^{1/3}
// (η the sun's elevation; the cube root spends more control on low suns), blended linearly
// between the two integer turbidities around T and between ground albedo 0 and 1.
// Sun (per channel): a piecewise cubic in the sun's elevation (45 pieces, piece i starting
// at (i/45)³·90°) per integer turbidity, blended linearly in turbidity, for the disc's
// centre; across the disc it falls off by the limb-darkening polynomial of degree 5 in
// μ = cos of the angle at which the solar surface is seen (μ = √(1 − (sin γ / sin r)²)).
// Radiance is in W m⁻² sr⁻¹ nm⁻¹, the datasets' unit.
//
// Between channels radiance is linear in wavelength. Outside 320–720 nm (the renderer
// transports 360–830 nm, and more with --spectral-range) it holds the end channel's value:
// the datasets say nothing there, a hold is continuous (a taper to 0 would invent a dark
// band), and what it decides is small: ȳ over 720–830 nm is 0.013 % of its integral.
#pragma once
#include <array>
#include <cmath>

namespace spt {

inline constexpr int kSkyChannels = 11;
inline constexpr float kSkyFirstChannelNm = 320.f, kSkyChannelStepNm = 40.f;

/// Which channels a wavelength lies between: the lower one and the upper one's weight.
struct SkyChannelLerp {
    int lower;
    float upper_weight;
};
inline SkyChannelLerp sky_channel_lerp(float lambda_nm) {
    const float x = (lambda_nm - kSkyFirstChannelNm) / kSkyChannelStepNm;
    if (!(x > 0.f)) return {0, 0.f};  // below 320 nm (and NaN): hold channel 0
    if (x >= static_cast<float>(kSkyChannels - 1)) return {kSkyChannels - 2, 1.f};  // above 720 nm: hold
    const int i = static_cast<int>(x);
    return {i, x - static_cast<float>(i)};
}

/// The sky dome's parameters for one sun elevation, turbidity and ground albedo.
struct HosekWilkieSky {
    /// Per channel: A … I of the formula (H the Mie lobe's anisotropy) and L_M.
    struct Channel {
        float A, B, C, D, E, F, G, H, I, L_M;
    };
    std::array<Channel, kSkyChannels> channels{};

    /// elevation in radians within [0, π/2], turbidity in [1, 10], albedo in [0, 1] (the
    /// caller checks; values outside are clamped).
    static HosekWilkieSky make(double elevation, double turbidity, double albedo);

    /// Radiance of channel c along a view of zenith cosine cos_theta ≥ 0 at angle gamma
    /// (cosine cos_gamma) from the sun; negative fits are clamped to 0.
    float radiance(int c, float cos_theta, float gamma, float cos_gamma) const {
        const Channel& p = channels[static_cast<std::size_t>(c)];
        const float mie_denominator = 1.f + p.H * p.H - 2.f * p.H * cos_gamma;
        const float chi = (1.f + cos_gamma * cos_gamma) / (mie_denominator * std::sqrt(mie_denominator));
        const float f = (1.f + p.A * std::exp(p.B / (cos_theta + 0.01f))) *
                        (p.C + p.D * std::exp(p.E * gamma) + p.F * cos_gamma * cos_gamma + p.G * chi +
                         p.I * std::sqrt(cos_theta));
        return f > 0.f ? f * p.L_M : 0.f;
    }
};

/// The solar radiance function for one sun elevation and turbidity.
struct HosekWilkieSun {
    std::array<float, kSkyChannels> centre{};  ///< radiance at the disc's centre
    std::array<std::array<float, 6>, kSkyChannels> limb{};  ///< limb darkening, by power of μ

    static HosekWilkieSun make(double elevation, double turbidity);

    /// Limb darkening of channel c at μ (1 at the centre).
    float darkening(int c, float mu) const {
        const auto& k = limb[static_cast<std::size_t>(c)];
        return k[0] + mu * (k[1] + mu * (k[2] + mu * (k[3] + mu * (k[4] + mu * k[5]))));
    }
    /// Radiance of channel c at μ.
    float radiance(int c, float mu) const {
        const float v = centre[static_cast<std::size_t>(c)] * darkening(c, mu);
        return v > 0.f ? v : 0.f;
    }
};

/// Weights w_c with Σ_c w_c·v_c the mean over 380, 390, …, 780 nm (power()'s mean) of the
/// spectrum linear between channel values v_c (held beyond the ends).
std::array<double, kSkyChannels> sky_channel_mean_weights();

/// Weights with Σ_c w_c·v_c the CIE 1931 luminance Y (equal-energy white = 1) of that
/// spectrum over 360–830 nm.
std::array<double, kSkyChannels> sky_channel_luminance_weights();

}  // namespace spt
