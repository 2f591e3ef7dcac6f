// Binning of analytic sources and the range scan used to validate materials.
#include "spectral/spectrum.h"

#include <algorithm>

namespace spt {

std::vector<float> project_onto_bins(const SpectrumSource& source, int bins) {
    return project_onto_bins([&](double l) { return source.eval(l); }, bins);
}

std::vector<float> project_onto_bins(const std::function<double(double)>& source_eval, int bins) {
    const double lo = Spectrum::kBinMin, width = (Spectrum::kBinMax - Spectrum::kBinMin) / bins;
    // Midpoint samples of the source, kBinSubsamples per bin.
    const int samples = bins * kBinSubsamples;
    const double step = width / kBinSubsamples;
    std::vector<double> f(samples);
    double f_min = kInfinity, f_max = -kInfinity;
    for (int k = 0; k < samples; ++k) f[k] = source_eval(lo + (k + 0.5) * step);
    // The source's range (for the clamp below) from a 0.5 nm scan, which includes the
    // integer wavelengths where tabulated data has its points.
    for (double l = lo; l <= Spectrum::kBinMax; l += 0.5) {
        const double v = source_eval(l);
        f_min = std::min(f_min, v), f_max = std::max(f_max, v);
    }
    if (bins == 1) {
        double sum = 0;
        for (double v : f) sum += v;
        return {static_cast<float>(sum / samples)};
    }
    // Right-hand side b_i = ∫ f·φ_i, with φ_i the look-up's basis: a hat between the
    // neighbouring centres, the end ones held flat to the range's ends.
    std::vector<double> b(bins, 0.0);
    for (int k = 0; k < samples; ++k) {
        const double x = (k + 0.5) / kBinSubsamples - 0.5;  // position in bin-centre units
        if (x <= 0) { b[0] += f[k] * step; continue; }
        if (x >= bins - 1) { b[bins - 1] += f[k] * step; continue; }
        const int i = static_cast<int>(x);
        const double t = x - i;
        b[i] += (1 - t) * f[k] * step;
        b[i + 1] += t * f[k] * step;
    }
    // Gram matrix of the basis: tridiagonal, w·(2/3, 1/6) inside, 5/6 on the end diagonals.
    std::vector<double> diag(bins, 2.0 * width / 3.0), off(bins, width / 6.0);
    diag.front() = diag.back() = 5.0 * width / 6.0;
    // Thomas algorithm.
    for (int i = 1; i < bins; ++i) {
        const double m = off[i - 1] / diag[i - 1];
        diag[i] -= m * off[i - 1];
        b[i] -= m * b[i - 1];
    }
    std::vector<float> c(bins);
    double next = 0;
    for (int i = bins - 1; i >= 0; --i) {
        const double v = (b[i] - (i + 1 < bins ? off[i] * next : 0.0)) / diag[i];
        next = v;
        // The projection may overshoot sharp features; keep the source's own range.
        c[i] = static_cast<float>(std::clamp(v, f_min, f_max));
    }
    return c;
}

Spectrum::Spectrum(SpectrumSource source, SpectralResolution resolution)
    : m_source(std::move(source)) {
    m_constant = m_source.is_constant();
    if (m_constant) {
        m_constant_value = static_cast<float>(m_source.eval(550.0));
        m_max = m_min = m_constant_value;
        m_zero = m_constant_value == 0.f;
        return;
    }
    if (resolution.bins != SpectralResolution::kExact) {
        const int n = resolution.bins;
        m_inv_bin_width = static_cast<float>(n / double(kBinMax - kBinMin));
        m_lookup = project_onto_bins(m_source, n);
        // One bin is a constant; store it twice so the interpolating look-up needs no branch.
        if (n == 1) m_lookup.push_back(m_lookup[0]), m_inv_bin_width = 0.f;
        m_last_bin = static_cast<float>(m_lookup.size() - 1);
        m_max = *std::max_element(m_lookup.begin(), m_lookup.end());
        m_min = *std::min_element(m_lookup.begin(), m_lookup.end());
        m_lookup.push_back(m_lookup.back());
        return;
    }
    // Exact mode: scan the sampled range densely (0.5 nm) for the validation bounds.
    m_max = -kInfinity, m_min = kInfinity;
    for (double l = kLambdaMin; l <= kLambdaMax; l += 0.5) {
        const float v = static_cast<float>(m_source.eval(l));
        m_max = std::max(m_max, v), m_min = std::min(m_min, v);
    }
}

void Spectrum::assign_bins(std::span<const float> bins) {
    const std::size_t n = bins.size();
    m_constant = m_zero = false;
    // As the constructor lays them out: the bins, the last once more (one bin: twice more).
    m_lookup.resize(n == 1 ? 3 : n + 1);
    std::copy(bins.begin(), bins.end(), m_lookup.begin());
    std::fill(m_lookup.begin() + static_cast<std::ptrdiff_t>(n), m_lookup.end(), bins[n - 1]);
    m_inv_bin_width = n == 1 ? 0.f : static_cast<float>(n / double(kBinMax - kBinMin));
    m_last_bin = static_cast<float>(n == 1 ? 1 : n - 1);
    const auto [lo, hi] = std::minmax_element(bins.begin(), bins.end());
    m_min = *lo, m_max = *hi;
}

}  // namespace spt
