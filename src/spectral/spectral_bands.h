// The wavelength bands of a spectral image (--spectral-bands N --spectral-range MIN:MAX).
#pragma once
#include <cmath>

namespace spt {

/// `count` equal bands over [min_nm, max_nm]; band b is [min + b·Δ, min + (b + 1)·Δ).
struct SpectralBands {
    double min_nm = 360, max_nm = 830;
    int count = 0;  ///< 0: no spectral output

    double width_nm() const { return (max_nm - min_nm) / count; }
    double center_nm(int b) const { return min_nm + (b + 0.5) * width_nm(); }
    /// Band holding λ, or -1 outside [min_nm, max_nm) (λ = max_nm joins the last band).
    int band_of(double lambda_nm) const {
        if (!(lambda_nm >= min_nm && lambda_nm <= max_nm)) return -1;
        const int b = static_cast<int>((lambda_nm - min_nm) / width_nm());
        return b < count ? b : count - 1;
    }
};

}  // namespace spt
