// Binning of analytic sources and the range scan used to validate materials.
#include "spectral/spectrum.h"

#include <algorithm>

namespace spt {

Spectrum::Spectrum(SpectrumSource source, SpectralResolution resolution)
    : m_source(std::move(source)) {
    m_constant = m_source.is_constant();
    if (m_constant) {
        m_constant_value = static_cast<float>(m_source.eval(550.0));
        m_max = m_min = m_constant_value;
        return;
    }
    if (resolution.bins != SpectralResolution::kExact) {
        const int n = resolution.bins;
        const double width = (kBinMax - kBinMin) / n;
        m_inv_bin_width = static_cast<float>(1.0 / width);
        // One bin is a constant; store it twice so the interpolating look-up needs no branch.
        m_bins.resize(std::max(n, 2));
        m_last_bin = static_cast<float>(m_bins.size() - 1);
        for (int i = 0; i < n; ++i)
            m_bins[i] = static_cast<float>(m_source.eval(kBinMin + (i + 0.5) * width));
        if (n == 1) m_bins[1] = m_bins[0], m_inv_bin_width = 0.f;
        m_max = *std::max_element(m_bins.begin(), m_bins.end());
        m_min = *std::min_element(m_bins.begin(), m_bins.end());
        return;
    }
    // Exact mode: scan the sampled range densely (0.5 nm) for the validation bounds.
    m_max = -kInfinity, m_min = kInfinity;
    for (double l = kLambdaMin; l <= kLambdaMax; l += 0.5) {
        const float v = static_cast<float>(m_source.eval(l));
        m_max = std::max(m_max, v), m_min = std::min(m_min, v);
    }
}

}  // namespace spt
