// Fluorescence: a surface that absorbs light at one wavelength λi and re-emits part of it,
// diffusely, at a longer one λo (a bispectral surface). A fluorescent material is a dye layer
// (this re-radiation part, Material::fluorescence) over a surface of any BSDF type of the set
// (the reflectance part, Material::bsdf).
//
// The re-radiation part: absorptance a(λ) = 1 − 10^(−d·ε(λ)) of a dye layer of optical density
// d at the excitation band's peak (ε: the excitation spectrum, peak 1; Beer–Lambert, one pass),
// quantum yield Φ (photons emitted per photon absorbed) and emission spectrum e(λ) in photons per
// nm with ∫e dλ = 1. An absorbed photon of energy hc/λi comes back as one of hc/λo with
// probability Φ·e(λo)dλo, so in energy (radiance) units the bispectral radiance factor (the
// Donaldson matrix, Donaldson 1954; Hullin et al. 2010, "Fluorescent immersion range scanning")
// is, per nm of λi,
//     D(λi, λo) = a(λi) · Φ · e(λo) · (λi/λo) · [λi < λo],
// and the re-emitted radiance, Lambertian,
//     Lo(λo) = ∫ dλi ∫ dωi  D(λi, λo)/π · Li(λi, ωi) · |cos θi|.
// Energy: the indicator (Stokes' rule: emission only at longer wavelengths) makes λi/λo ≤ 1,
// so the energy re-emitted from light absorbed at λi is ∫D dλo ≤ a(λi)·Φ ≤ a(λi). The surface
// under the layer receives what the layer lets through: the reflectance part is
//     f(ωo, ωi, λ) = (1 − a(λ)) · f_surface(ωo, ωi, λ)
// (one pass, as a(λ) is defined; material "fluorescent", scenes/README.md), whose albedo is
// ≤ 1 − a(λ), so reflected plus re-emitted energy ≤ 1 − a + a·Φ ≤ 1 at every λi, whatever the
// surface (tests/test_fluorescence.cpp: the white furnace). The factor 1 − a(λ) is applied by
// the integrator wherever the reflectance part is evaluated or sampled (passed()); the
// surface's own BSDF, its densities and so the MIS weights are those of its type.
//
// Transport range: λi is sampled over [kTransportMin, kTransportMax] = [300, 830] nm, wider than
// the film's [360, 830] (kLambdaMin: the observer's CMFs are 0 below 360 nm, so a camera path
// never starts there, but UV-A light at 315–400 nm excites dyes that glow in the visible).
// 300 nm: the CIE D65 table starts there, and sunlight below ~295 nm is absorbed by ozone.
// Spectra are tabulated at 1 nm over this range, piecewise constant; sampling and evaluation
// read the same tables, so the estimator's weights are exact.
//
// With hero wavelengths (Wilkie et al. 2014), camera paths: at a fluorescent vertex the path
// reflects with probability P (weight 1/P) or re-emits with 1 − P. Re-emission draws one
// excitation wavelength λi from
//     p(λi) = ½·a(λi)/A + ½·a(λi)·S(λi)/B,   A = ∫ a dλ,  B = ∫ a·S dλ  over the transport range,
// S the summed spectral power of the scene's lights (Scene::finalize; p = a/A without
// lights or where B = 0): what the dye absorbs, half of it weighted by what the lights emit,
// so a dye's weak UV band under a UV lamp is not left to rare samples, while the defensive
// half keeps every absorbing wavelength at p ≥ a/(2A) (the weights below stay ≤ 2·A·Φ).
// A direction is drawn from cos θi/π, and every lane j (emitted wavelength λj) multiplies its
// throughput by
//     D(λi, λj)/π·cos θi / (p(λi)·cos θi/π·(1 − P)) = D(λi, λj) / (p(λi)·(1 − P));
// then all four lanes continue at the one wavelength λi (the integrator restores the film's
// wavelengths at the end of the path). Unbiased for every lane: p(λi) and the direction's
// density do not depend on λj, so (λi, ωi) is a valid sample of each lane's integral, and
// given the four wavelengths the branch's expectation is (1 − P)·D/((1 − P)·p)·p = D. No
// companion is terminated, unlike a dispersive refraction (sampled.h), whose direction belongs
// to one wavelength; a path whose companions were terminated before keeps only the hero's.
// (Collapsing to the hero alone, as dispersion does, is also unbiased but brings one emitted
// wavelength per re-emission instead of four: more colour noise.)
// P depends on the four wavelengths only:
//     P = r/(r + w) clamped to [0.05, 0.95],  r = mean over the lanes of (1 − a(λj)) times
//     the surface's reflectance (a diffuse surface's kd; 1 for other types, whose albedo
//     depends on the direction),
//     w = mean over the lanes of A·Φ·e(λj) (the re-emission's expected weight under a flat
//     illuminant, without the Stokes cut); P = 1 where w = 0 (nothing re-emitted at these
//     wavelengths), 0 where the reflectance part is black.
// Next-event estimation at a fluorescent vertex estimates both parts, always: the reflectance
// part with the path's wavelengths, the re-emission with its own λi (drawn from p, weights
// D/p, no branch) through a white Lambertian lobe; only the continuation chooses a branch. Each
// part's light and BSDF strategies are combined by the power heuristic over directions: both
// draw λi from the same p, so the wavelength's density cancels from the weights, and the
// continuation's emission found is weighted with the density of the branch it took (the
// surface BSDF's, or cos θi/π), divided by that branch's probability.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "model/bsdfs/bsdf.h"
#include "spectral/spectrum_source.h"

namespace spt {

/// Range over which excitation wavelengths are sampled (nm); see the header comment.
inline constexpr float kTransportMin = 300.f, kTransportMax = 830.f;
/// The 1 nm bins the dye's spectra are tabulated in over that range.
inline constexpr int kTransportBins = static_cast<int>(kTransportMax - kTransportMin);

class Fluorescence {
public:
    /// excitation: the dye's relative absorption spectrum (its peak is normalised to 1 over the
    /// transport range); emission: its relative photon spectrum (normalised to ∫ = 1);
    /// density: optical density d at the excitation peak (> 0); quantum_yield Φ in [0, 1].
    Fluorescence(const SpectrumSource& excitation, const SpectrumSource& emission, double density,
                 double quantum_yield, std::string dye);

    /// Absorptance a(λ) (0 outside the transport range).
    float absorptance(float lambda_nm) const { return lookup(m_absorptance, lambda_nm); }
    /// 1 − a(λ) at each lane's wavelength: the factor on the surface's BSDF under the layer.
    SampledSpectrum passed(const SampledWavelengths& lambda) const {
        SampledSpectrum t;
        for (int j = 0; j < kLambdaCount; ++j) t[j] = 1.f - absorptance(lambda.lambda[j]);
        return t;
    }
    /// Emission e(λ) per nm, ∫ e = 1 (0 outside the transport range).
    float emission(float lambda_nm) const { return lookup(m_emission, lambda_nm); }
    float quantum_yield() const { return m_quantum_yield; }
    /// A = ∫ a dλ over the transport range (nm).
    float absorbed_integral() const { return m_absorbed_integral; }
    const std::string& dye() const { return m_dye; }

    /// D(λi, λo) per nm of λi (header comment).
    float donaldson(float lambda_i, float lambda_o) const {
        if (!(lambda_i < lambda_o)) return 0.f;
        return absorptance(lambda_i) * m_quantum_yield * emission(lambda_o) * (lambda_i / lambda_o);
    }
    /// w(λo) = A·Φ·e(λo): the expected weight of re-emission at λo, for the branch choice.
    float reemission_weight(float lambda_o) const { return m_absorbed_integral * m_quantum_yield * emission(lambda_o); }

    /// Excitation sampling by the lights' summed spectral power S (header comment), one value
    /// per 1 nm bin from kTransportMin (a light_spectral_power at each bin's centre).
    void sample_excitation_by(const std::vector<double>& illumination);
    /// λi drawn from p(λi) for u in [0, 1); its density in `pdf`.
    float sample_excitation(float u, float& pdf) const;
    /// p(λi) (header comment): a(λi)/A until sample_excitation_by.
    float excitation_pdf(float lambda_nm) const { return lookup(m_pdf, lambda_nm); }

    /// The lobe a re-emitting vertex scatters with: white Lambertian (the spectral weight is in
    /// the path's throughput).
    const Bsdf& lobe() const { return m_lobe; }

private:
    static float lookup(const std::vector<float>& table, float lambda_nm) {
        const float x = lambda_nm - kTransportMin;
        if (!(x >= 0.f && x < kTransportMax - kTransportMin)) return 0.f;
        return table[static_cast<std::size_t>(x)];
    }

    std::vector<float> m_absorptance;  ///< per 1 nm bin from kTransportMin
    std::vector<float> m_emission;     ///< per 1 nm bin, sums to 1
    std::vector<float> m_pdf;          ///< p(λi) per 1 nm bin, sums to 1
    std::vector<float> m_cdf;          ///< of m_pdf, m_cdf[0] = 0, last = 1
    float m_absorbed_integral = 0.f;
    float m_quantum_yield = 0.f;
    std::string m_dye;
    Bsdf m_lobe;
};

/// Re-emission drawn by one number: λi from p(λi), every lane's wavelength set to it and its
/// throughput multiplied by D(λi, λj)/(p(λi)·p_branch). False when nothing is carried (λi not
/// below any lane's wavelength).
bool reemit(const Fluorescence& fl, SampledWavelengths& lambda, SampledSpectrum& beta, float u_lambda,
            float p_branch);

/// Reflect or re-emit at a fluorescent vertex of a camera path (header comment): returns the
/// BSDF the vertex scatters with (`surface`, after weighting `beta` by (1 − a)/P, or the white
/// lobe after reemit()), or nullptr when the re-emission carries nothing. u_branch, u_lambda
/// in [0, 1).
const Bsdf* fluoresce_or_reflect(const Fluorescence& fl, const Bsdf& surface, SampledWavelengths& lambda,
                                 SampledSpectrum& beta, float u_branch, float u_lambda);

}  // namespace spt
