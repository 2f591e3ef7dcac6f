#include "render/film.h"

#include <cmath>

namespace spt {

Film::Film(int width, int height)
    : m_width(width),
      m_height(height),
      m_xyz(3 * static_cast<std::size_t>(width) * height, 0.0),
      m_y_squared(static_cast<std::size_t>(width) * height, 0.0),
      m_count(static_cast<std::size_t>(width) * height, 0) {}

Xyz Film::pixel_xyz(int x, int y) const {
    const std::size_t i = index(x, y);
    if (m_count[i] == 0) return {};
    const double inv = 1.0 / m_count[i];
    return {m_xyz[3 * i] * inv, m_xyz[3 * i + 1] * inv, m_xyz[3 * i + 2] * inv};
}

double Film::pixel_y_standard_error(int x, int y) const {
    const std::size_t i = index(x, y);
    const double n = m_count[i];
    if (n < 2) return 0.0;
    const double mean = m_xyz[3 * i + 1] / n;
    const double variance = std::max(0.0, (m_y_squared[i] / n - mean * mean) * n / (n - 1));
    return std::sqrt(variance / n);
}

Image Film::develop(const ColorSpace& space) const {
    Image image;
    image.width = m_width;
    image.height = m_height;
    image.rgb.resize(3 * static_cast<std::size_t>(m_width) * m_height);
    for (int y = 0; y < m_height; ++y)
        for (int x = 0; x < m_width; ++x) {
            const auto rgb = apply(space.from_xyz, pixel_xyz(x, y));
            float* out = image.pixel(x, y);
            for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(rgb[c]);
        }
    return image;
}

}  // namespace spt
