// Wavelength sampling for spectral output beyond the visible (--spectral-range 300:1100): the
// visible density of sampled.h mixed half and half with a uniform density over the whole
// range, so that every wavelength of the range has a non-zero pdf while half the samples keep
// serving the eye-weighted XYZ film (unbiased: it divides by the same mixture pdf).
#pragma once
#include <algorithm>

#include "spectral/sampled.h"

namespace spt {

struct WideWavelengthSampling {
    float min_nm = kLambdaMin, max_nm = kLambdaMax;  ///< covers [360, 830] and the requested range

    /// The range sampled for output over [lo, hi] nm: its union with [360, 830].
    static WideWavelengthSampling covering(float lo, float hi) {
        return {std::min(lo, kLambdaMin), std::max(hi, kLambdaMax)};
    }

    /// Density per nm: ½·visible_wavelength_pdf + ½·uniform over [min_nm, max_nm].
    float pdf(float lambda_nm) const {
        const bool inside = lambda_nm >= min_nm && lambda_nm <= max_nm;
        const float uniform = inside ? 1.f / (max_nm - min_nm) : 0.f;
        return 0.5f * visible_wavelength_pdf(lambda_nm) + 0.5f * uniform;
    }

    /// Hero and companions from u + k/K (mod 1), as SampledWavelengths::sample: a lane's
    /// number below ½ picks the uniform part, the rest the visible one (so two lanes each).
    /// Every lane carries the mixture pdf, its density whichever part drew it.
    SampledWavelengths sample(float u) const {
        SampledWavelengths w;
        for (int k = 0; k < kLambdaCount; ++k) {
            float uk = u + static_cast<float>(k) / kLambdaCount;
            if (uk >= 1.f) uk -= 1.f;
            const float lambda =
                uk < 0.5f ? min_nm + 2.f * uk * (max_nm - min_nm)
                          : sample_visible_wavelength(std::min(2.f * uk - 1.f, 0x1.fffffep-1f));
            w.lambda[k] = lambda;
            w.pdf[k] = pdf(lambda);
        }
        return w;
    }
};

}  // namespace spt
