// Loads the colour matching functions from the table compiled into the program.
#include "spectral/cie.h"

#include <stdexcept>

#include "spectral/spectral_table.h"

namespace spt {

const Cie1931& Cie1931::get() {
    static const Cie1931 instance;
    return instance;
}

Cie1931::Cie1931() {
    const SpectralTable& table = embedded_spectral_table("cie_1931_2deg.csv");
    const auto& l = table.wavelengths_nm;
    const auto &xs = table.column("x_bar"), &ys = table.column("y_bar"), &zs = table.column("z_bar");
    // The fast look-up assumes exactly one entry per nanometre over the sampled range.
    if (l.front() != kLambdaMin || l.back() != kLambdaMax || l.size() != 471)
        throw std::runtime_error("spectra/cie_1931_2deg.csv must cover 360-830 nm at 1 nm");
    m_last = static_cast<float>(l.size() - 1);
    for (std::size_t i = 0; i < l.size(); ++i)
        m_rows.push_back(Float4{static_cast<float>(xs[i]), static_cast<float>(ys[i]), static_cast<float>(zs[i]), 0.f});
    // Trapezoid rule = exact integral of the linearly interpolated table we evaluate.
    for (std::size_t i = 0; i + 1 < l.size(); ++i)
        m_y_integral += 0.5 * (static_cast<double>(m_rows[i][1]) + m_rows[i + 1][1]);
}

}  // namespace spt
