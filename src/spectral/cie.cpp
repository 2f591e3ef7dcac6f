// Loads the colour matching functions from the table compiled into the program.
#include "spectral/cie.h"

#include <stdexcept>

#include "spectral/spectral_table.h"

namespace spt {

namespace {

Observer load_cie1931() {
    const SpectralTable& table = embedded_spectral_table("cie_1931_2deg.csv");
    const auto& l = table.wavelengths_nm;
    const auto &xs = table.column("x_bar"), &ys = table.column("y_bar"), &zs = table.column("z_bar");
    if (l.front() != kLambdaMin || l.back() != kLambdaMax || l.size() != Observer::kRows)
        throw std::runtime_error("spectra/cie_1931_2deg.csv must cover 360-830 nm at 1 nm");
    std::vector<Float4> rows;
    for (std::size_t i = 0; i < l.size(); ++i)
        rows.push_back(Float4{static_cast<float>(xs[i]), static_cast<float>(ys[i]),
                              static_cast<float>(zs[i]), 0.f});
    return Observer("CIE 1931 2 degree", rows);
}

}  // namespace

const Observer& Cie1931::get() {
    static const Observer instance = load_cie1931();
    return instance;
}

double luminance(const SpectrumSource& s) {
    const Observer& cie = Cie1931::get();
    double sy = 0, y = 0;
    for (int l = static_cast<int>(kLambdaMin); l <= static_cast<int>(kLambdaMax); ++l) {
        const double ybar = cie.cmf(static_cast<float>(l)).y;
        sy += s.eval(l) * ybar;
        y += ybar;
    }
    return sy / y;
}

}  // namespace spt
