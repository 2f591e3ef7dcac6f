#include "model/fluorescence.h"

#include <algorithm>
#include <cmath>

namespace spt {

namespace {

/// The cumulative sums of a density per 1 nm bin, scaled to end at 1 (when the density sums
/// to 0, all 0 but the last).
std::vector<float> cumulative(const std::vector<float>& pdf) {
    std::vector<double> c(pdf.size() + 1, 0.0);
    for (std::size_t k = 0; k < pdf.size(); ++k) c[k + 1] = c[k] + pdf[k];
    std::vector<float> cdf(c.size(), 0.f);
    for (std::size_t k = 0; k < c.size(); ++k) cdf[k] = c.back() > 0 ? static_cast<float>(c[k] / c.back()) : 0.f;
    cdf.back() = 1.f;
    return cdf;
}

/// A source's values at the centres of the transport range's 1 nm bins.
std::vector<float> tabulate(const SpectrumSource& s) {
    std::vector<float> t(kTransportBins);
    for (int k = 0; k < kTransportBins; ++k) t[k] = static_cast<float>(std::max(0.0, s.eval(kTransportMin + k + 0.5)));
    return t;
}

}  // namespace

Fluorescence::Fluorescence(const SpectrumSource& excitation, const SpectrumSource& emission, double density,
                           double quantum_yield, std::string dye)
    : m_quantum_yield(static_cast<float>(quantum_yield)), m_dye(std::move(dye)),
      m_lobe(DiffuseBsdf{Spectrum(SpectrumSource::constant(1.0), SpectralResolution{})}) {
    std::vector<float> eps = tabulate(excitation);
    const float peak = *std::max_element(eps.begin(), eps.end());
    m_absorptance.resize(kTransportBins);
    double sum = 0;
    for (int k = 0; k < kTransportBins; ++k) {
        const double rel = peak > 0.f ? eps[k] / peak : 0.0;
        m_absorptance[k] = static_cast<float>(1.0 - std::pow(10.0, -density * rel));
        sum += m_absorptance[k];
    }
    m_absorbed_integral = static_cast<float>(sum);  // bins of 1 nm
    m_pdf.resize(kTransportBins);
    for (int k = 0; k < kTransportBins; ++k) m_pdf[k] = sum > 0 ? static_cast<float>(m_absorptance[k] / sum) : 0.f;
    m_cdf = cumulative(m_pdf);
    m_emission = tabulate(emission);
    double total = 0;
    for (float e : m_emission) total += e;
    for (float& e : m_emission) e = total > 0 ? static_cast<float>(e / total) : 0.f;
}

void Fluorescence::sample_excitation_by(const std::vector<double>& illumination) {
    double lit = 0;
    for (int k = 0; k < kTransportBins; ++k) lit += m_absorptance[k] * std::max(0.0, illumination.at(k));
    if (!(lit > 0) || !(m_absorbed_integral > 0.f)) return;
    for (int k = 0; k < kTransportBins; ++k)
        m_pdf[k] = static_cast<float>(0.5 * m_absorptance[k] / m_absorbed_integral +
                                      0.5 * m_absorptance[k] * std::max(0.0, illumination[k]) / lit);
    m_cdf = cumulative(m_pdf);
}

float Fluorescence::sample_excitation(float u, float& pdf) const {
    // The bin whose cumulative interval holds u, then uniform inside it; empty bins have an
    // empty interval, so they are never chosen.
    const auto it = std::upper_bound(m_cdf.begin() + 1, m_cdf.end(), u);
    const int k = std::clamp(static_cast<int>(it - m_cdf.begin()) - 1, 0, kTransportBins - 1);
    const float width = m_cdf[k + 1] - m_cdf[k];
    const float t = width > 0.f ? std::clamp((u - m_cdf[k]) / width, 0.f, 0x1.fffffep-1f) : 0.5f;
    const float lambda = kTransportMin + static_cast<float>(k) + t;
    pdf = excitation_pdf(lambda);
    return lambda;
}

const Bsdf* fluoresce_or_reflect(const Fluorescence& fl, const Bsdf& surface, SampledWavelengths& lambda,
                                 SampledSpectrum& beta, float u_branch, float u_lambda) {
    float w = 0.f;
    for (int j = 0; j < kLambdaCount; ++j) w += fl.reemission_weight(lambda.lambda[j]);
    w /= kLambdaCount;
    const SampledSpectrum passed = fl.passed(lambda);
    float p_reflect = 1.f;
    if (w > 0.f) {
        // A diffuse surface's albedo is its kd; another type's depends on the direction and
        // is taken as 1 (the choice only moves variance, never the mean).
        SampledSpectrum r = passed;
        if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&surface)) r *= d->kd.sample(lambda);
        const float mean = r.average();
        p_reflect = mean > 0.f ? std::clamp(mean / (mean + w), 0.05f, 0.95f) : 0.f;
    }
    if (u_branch < p_reflect) {
        beta *= passed / p_reflect;
        return &surface;
    }
    return reemit(fl, lambda, beta, u_lambda, 1.f - p_reflect) ? &fl.lobe() : nullptr;
}

bool reemit(const Fluorescence& fl, SampledWavelengths& lambda, SampledSpectrum& beta, float u_lambda,
            float p_branch) {
    const bool terminated = lambda.secondary_terminated();
    float pdf = 0.f;
    const float lambda_i = fl.sample_excitation(u_lambda, pdf);
    if (!(pdf > 0.f)) return false;
    const float scale = 1.f / (pdf * p_branch);
    for (int j = 0; j < kLambdaCount; ++j) {
        beta[j] = j > 0 && terminated ? 0.f : beta[j] * fl.donaldson(lambda_i, lambda.lambda[j]) * scale;
        lambda.lambda[j] = lambda_i;
    }
    return !beta.is_zero();
}

}  // namespace spt
