#include "model/fluorescence.h"

#include <algorithm>
#include <cmath>

namespace spt {

namespace {

constexpr int kBins = static_cast<int>(kTransportMax - kTransportMin);

/// A source's values at the centres of the transport range's 1 nm bins.
std::vector<float> tabulate(const SpectrumSource& s) {
    std::vector<float> t(kBins);
    for (int k = 0; k < kBins; ++k) t[k] = static_cast<float>(std::max(0.0, s.eval(kTransportMin + k + 0.5)));
    return t;
}

}  // namespace

Fluorescence::Fluorescence(const SpectrumSource& excitation, const SpectrumSource& emission, double density,
                           double quantum_yield, std::string dye)
    : m_quantum_yield(static_cast<float>(quantum_yield)), m_dye(std::move(dye)),
      m_lobe(DiffuseBsdf{Spectrum(SpectrumSource::constant(1.0), SpectralResolution{})}) {
    std::vector<float> eps = tabulate(excitation);
    const float peak = *std::max_element(eps.begin(), eps.end());
    m_absorptance.resize(kBins);
    double sum = 0;
    m_cdf.assign(kBins + 1, 0.f);
    std::vector<double> cdf(kBins + 1, 0.0);
    for (int k = 0; k < kBins; ++k) {
        const double rel = peak > 0.f ? eps[k] / peak : 0.0;
        m_absorptance[k] = static_cast<float>(1.0 - std::pow(10.0, -density * rel));
        sum += m_absorptance[k];
        cdf[k + 1] = sum;
    }
    m_absorbed_integral = static_cast<float>(sum);  // bins of 1 nm
    for (int k = 0; k <= kBins; ++k) m_cdf[k] = sum > 0 ? static_cast<float>(cdf[k] / sum) : 0.f;
    m_cdf[kBins] = 1.f;
    m_emission = tabulate(emission);
    double total = 0;
    for (float e : m_emission) total += e;
    for (float& e : m_emission) e = total > 0 ? static_cast<float>(e / total) : 0.f;
}

float Fluorescence::sample_excitation(float u, float& pdf) const {
    // The bin whose cumulative interval holds u, then uniform inside it; empty bins have an
    // empty interval, so they are never chosen.
    const auto it = std::upper_bound(m_cdf.begin() + 1, m_cdf.end(), u);
    const int k = std::clamp(static_cast<int>(it - m_cdf.begin()) - 1, 0, kBins - 1);
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
