// Spectrum: an analytic source plus its N-bin sampling over [380, 780] nm. The renderer
// evaluates the bins (fast, the default) or the source itself (--spectral-bins exact).
#pragma once
#include <cstring>
#include <functional>
#include <span>
#include <vector>

#include "spectral/sampled.h"
#include "spectral/spectrum_source.h"

namespace spt {

/// Midpoint samples per bin used to project a source onto the bins.
inline constexpr int kBinSubsamples = 64;

/// Bin values of `source` for N bins over [380, 780] nm: the least-squares (L2) projection
/// onto the look-up's own basis (hats between bin centres, the end ones held flat), clamped
/// to the source's range. Point samples at the centres alias tabulated data with structure
/// finer than a bin (the 5 nm lines of D65): ColorChecker under D65 at 16 bins goes from mean
/// ΔE2000 0.56 (point samples) to 0.15 (see validation/results/color_accuracy.md).
std::vector<float> project_onto_bins(const SpectrumSource& source, int bins);
/// The same projection for any function of λ (nm): a texel's spectrum that is no single
/// source, such as an RGB fit times an illuminant.
std::vector<float> project_onto_bins(const std::function<double(double)>& f, int bins);

/// How spectra are represented in a scene: N bins, or exact evaluation of the sources.
struct SpectralResolution {
    static constexpr int kExact = 0;
    static constexpr int kMinBins = 1, kMaxBins = 1024, kDefaultBins = 16;
    int bins = kDefaultBins;  ///< kExact (0) means no binning
    /// The bin count was not chosen by the user: a scene whose lights have narrow lines gets
    /// more (spectral/line_spectra.h, build_scene).
    bool automatic = false;
};

class Spectrum {
public:
    static constexpr float kBinMin = 380.f, kBinMax = 780.f;

    Spectrum() : Spectrum(SpectrumSource::constant(0.0), SpectralResolution{}) {}
    Spectrum(SpectrumSource source, SpectralResolution resolution);

    /// Value at λ (nm): bin values (project_onto_bins) sit at the bin centres, linearly
    /// interpolated between centres and held constant beyond the first and last centre. Exact mode evaluates the source.
    float eval(float lambda_nm) const {
        if (m_constant) return m_constant_value;
        if (m_lookup.empty()) return static_cast<float>(m_source.eval(lambda_nm));
        // Clamping the bin coordinate holds the end values and keeps the look-up branch-free.
        const float x = std::clamp((lambda_nm - kBinMin) * m_inv_bin_width - 0.5f, 0.f, m_last_bin);
        const int i = static_cast<int>(x);
        return lerp(x - static_cast<float>(i), m_lookup[i], m_lookup[i + 1]);
    }

    /// Values at the path's wavelengths: eval() on four lanes at once.
    [[gnu::always_inline]] SampledSpectrum sample(const SampledWavelengths& w) const {
        if (m_constant) return SampledSpectrum(m_constant_value);
        if (m_lookup.empty()) [[unlikely]] {
            SampledSpectrum s;
            for (int i = 0; i < kLambdaCount; ++i) s[i] = eval(w.lambda[i]);
            return s;
        }
        Float4 lambda;
        std::memcpy(&lambda, w.lambda.data(), sizeof lambda);
        const Float4 x = min4(max4((lambda - kBinMin) * m_inv_bin_width - 0.5f, splat4(0.f)),
                              splat4(m_last_bin));
        const Int4 i = to_int4(x);
        const Float4 t = x - to_float4(i);
        const float* b = m_lookup.data();
        const Float4 lo = {b[i[0]], b[i[1]], b[i[2]], b[i[3]]};
        const Float4 hi = {b[i[0] + 1], b[i[1] + 1], b[i[2] + 1], b[i[3] + 1]};
        return SampledSpectrum((1.f - t) * lo + t * hi);
    }

    /// Makes this the binned spectrum of these bin values (a texture's value at a point):
    /// the look-up, bounds and flags follow them. Reuses the storage, so a spectrum that
    /// has held as many bins before allocates nothing. The analytic source is left as it
    /// was; only the checks at load time read it.
    void assign_bins(std::span<const float> bins);

    const SpectrumSource& source() const { return m_source; }
    /// The bin values (empty in exact mode).
    std::span<const float> bins() const {
        return m_lookup.empty() ? std::span<const float>() : std::span<const float>(m_lookup).first(m_lookup.size() - 1);
    }
    bool is_constant() const { return m_constant; }
    bool is_zero() const { return m_zero; }
    /// Largest and smallest value the renderer can see (bins, or a dense scan in exact mode).
    float max_value() const { return m_max; }
    float min_value() const { return m_min; }

private:
    SpectrumSource m_source;
    /// The bin values, then the last one again: at the last centre the look-up reads one past
    /// it with weight 0, so it needs no clamp of the index. Empty in exact mode.
    std::vector<float> m_lookup;
    float m_inv_bin_width = 0.f;
    float m_last_bin = 0.f;     ///< index of the last bin, as a float
    bool m_constant = false;
    bool m_zero = false;  ///< constant 0: material lobe tests read one byte per bounce
    float m_constant_value = 0.f;
    float m_max = 0.f, m_min = 0.f;
};

}  // namespace spt
