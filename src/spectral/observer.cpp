// The response table and its normaliser.
#include "spectral/observer.h"

#include <stdexcept>

namespace spt {

Observer::Observer(std::string name, const std::vector<Float4>& rows)
    : m_name(std::move(name)), m_rows(rows) {
    // The fast look-up assumes exactly one entry per nanometre over the sampled range.
    if (m_rows.size() != kRows)
        throw std::invalid_argument("an observer needs 471 rows (360-830 nm at 1 nm)");
    for (Float4& r : m_rows) r[3] = 0.f;
    m_last = static_cast<float>(m_rows.size() - 1);
    // Trapezoid rule = exact integral of the linearly interpolated table we evaluate.
    for (std::size_t i = 0; i + 1 < m_rows.size(); ++i)
        m_y_integral += 0.5 * (static_cast<double>(m_rows[i][1]) + m_rows[i + 1][1]);
    if (!(m_y_integral > 0.0))
        throw std::invalid_argument(m_name + ": the second response (y or g) integrates to zero");
}

std::uint64_t Observer::fingerprint() const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    const auto* bytes = reinterpret_cast<const unsigned char*>(m_rows.data());
    for (std::size_t i = 0; i < m_rows.size() * sizeof(Float4); ++i)
        h = (h ^ bytes[i]) * 0x100000001b3ull;
    return h;
}

}  // namespace spt
