#include "spectral/rgb_texels.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "spectral/cie.h"
#include "spectral/rgb_to_spectrum.h"
#include "spectral/catalog_lookup.h"
#include "spectral/spectrum.h"

namespace spt {

namespace {

/// D65 as a source, and the factor that brings its luminance (cie_luminance) to 1.
struct UnitD65 {
    SpectrumSource d65;
    double inv_y = 1;

    static const UnitD65& get() {
        static const UnitD65 u;
        return u;
    }

private:
    UnitD65() {
        const SpectralTable& t = embedded_spectral_table("cie_d65.csv");
        d65 = column_spectrum(t, "value");
        inv_y = 1.0 / cie_luminance(d65);
    }
};

}  // namespace

double d65_unit_luminance(double lambda_nm) {
    const UnitD65& u = UnitD65::get();
    return u.d65.eval(lambda_nm) * u.inv_y;
}

std::vector<float> rgb_texel_bins(const std::array<float, 3>& rgb, TexelUse use, int bins) {
    for (float c : rgb) {
        if (!std::isfinite(c) || c < 0.f)
            throw std::invalid_argument("an RGB component is " + std::to_string(c) + "; expected a finite value >= 0");
        if (use == TexelUse::reflectance && c > 1.f)
            throw std::invalid_argument("a reflectance component is " + std::to_string(c) + "; expected at most 1");
    }
    if (use == TexelUse::reflectance) return project_onto_bins(rgb_to_spectrum({rgb[0], rgb[1], rgb[2]}), bins);
    const double scale = 2.0 * std::max({rgb[0], rgb[1], rgb[2]});
    if (scale == 0) return std::vector<float>(static_cast<std::size_t>(bins), 0.f);
    // Halving keeps the fitted colour inside (0, 1/2], far from the sigmoid's saturation.
    const SpectrumSource shape = rgb_to_spectrum({rgb[0] / scale, rgb[1] / scale, rgb[2] / scale});
    return project_onto_bins([&](double l) { return scale * shape.eval(l) * d65_unit_luminance(l); }, bins);
}

}  // namespace spt
