#include "render/film.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace spt {

Film::Film(int width, int height, const Observer& observer)
    : m_width(width),
      m_height(height),
      m_observer(&observer),
      m_xyz(3 * static_cast<std::size_t>(width) * height, 0.0),
      m_y_squared(static_cast<std::size_t>(width) * height, 0.0),
      m_count(static_cast<std::size_t>(width) * height, 0) {}

Xyz Film::pixel_xyz(int x, int y) const {
    const std::size_t i = index(x, y);
    Xyz c;
    if (m_count[i] > 0) {
        const double inv = 1.0 / m_count[i];
        c = {m_xyz[3 * i] * inv, m_xyz[3 * i + 1] * inv, m_xyz[3 * i + 2] * inv};
    }
    if (const double m = light_paths_per_pixel(); m > 0 && !m_splat_xyz.empty()) {
        const double inv = 1.0 / m;
        c.x += m_splat_xyz[3 * i] * inv, c.y += m_splat_xyz[3 * i + 1] * inv, c.z += m_splat_xyz[3 * i + 2] * inv;
    }
    return c;
}

double Film::pixel_y_standard_error(int x, int y) const {
    const std::size_t i = index(x, y);
    const double n = m_count[i];
    if (n < 2) return 0.0;
    const double mean = m_xyz[3 * i + 1] / n;
    const double variance = std::max(0.0, (m_y_squared[i] / n - mean * mean) * n / (n - 1));
    // Splats: each light path adds c_k to this pixel (mostly 0), so the variance of Σc_k/M is
    // about Σc_k²/M² (the splats' squares; their mean is negligible next to them per path).
    double splat_variance = 0.0;
    if (const double m = light_paths_per_pixel(); m > 0 && !m_splat_y_squared.empty())
        splat_variance = m_splat_y_squared[i] / (m * m);
    return std::sqrt(variance / n + splat_variance);
}

namespace {

template <typename T>
void append_array(std::string& out, const std::vector<T>& v) {
    out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <typename T>
void read_array(std::string_view& in, std::vector<T>& v) {
    const std::size_t n = v.size() * sizeof(T);
    if (in.size() < n) throw std::runtime_error("film state is truncated");
    std::memcpy(v.data(), in.data(), n);
    in.remove_prefix(n);
}

}  // namespace

std::string Film::save_state() const {
    std::string out;
    const std::uint64_t counters[2] = {rejected_nonfinite(), rejected_negative()};
    out.append(reinterpret_cast<const char*>(counters), sizeof counters);
    append_array(out, m_xyz);
    append_array(out, m_y_squared);
    append_array(out, m_count);
    if (has_splats()) {  // bdpt films only, so path-tracer checkpoints keep their layout
        out.append(reinterpret_cast<const char*>(&m_light_paths), sizeof m_light_paths);
        append_array(out, m_splat_xyz);
        append_array(out, m_splat_y_squared);
    }
    return out;
}

void Film::restore_state(std::string_view in) {
    std::uint64_t counters[2];
    if (in.size() < sizeof counters) throw std::runtime_error("film state is truncated");
    std::memcpy(counters, in.data(), sizeof counters);
    in.remove_prefix(sizeof counters);
    read_array(in, m_xyz);
    read_array(in, m_y_squared);
    read_array(in, m_count);
    if (!in.empty()) {
        if (in.size() < sizeof m_light_paths) throw std::runtime_error("film state is truncated");
        std::memcpy(&m_light_paths, in.data(), sizeof m_light_paths);
        in.remove_prefix(sizeof m_light_paths);
        allocate_splats();
        read_array(in, m_splat_xyz);
        read_array(in, m_splat_y_squared);
    }
    if (!in.empty()) throw std::runtime_error("film state has trailing bytes");
    m_rejected_nonfinite = counters[0];
    m_rejected_negative = counters[1];
}

void Film::enable_bands(const SpectralBands& bands) {
    m_bands = bands;
    m_band_sums.assign(static_cast<std::size_t>(bands.count) * m_count.size(), 0.0);
}

void Film::add_to_bands(std::size_t i, const SampledSpectrum& L, const SampledWavelengths& lambda) {
    double* sums = &m_band_sums[i * static_cast<std::size_t>(m_bands.count)];
    const double scale = 1.0 / (kLambdaCount * m_bands.width_nm());
    for (int k = 0; k < kLambdaCount; ++k) {
        const int b = m_bands.band_of(lambda.lambda[k]);
        if (b >= 0 && lambda.pdf[k] > 0.f)
            sums[b] += static_cast<double>(L[k]) / lambda.pdf[k] * scale;
    }
}

std::vector<float> Film::develop_bands() const {
    const auto n = static_cast<std::size_t>(m_bands.count);
    std::vector<float> out(m_band_sums.size(), 0.f);
    for (std::size_t i = 0; i < m_count.size(); ++i)
        if (m_count[i] > 0)
            for (std::size_t b = 0; b < n; ++b)
                out[i * n + b] = static_cast<float>(m_band_sums[i * n + b] / m_count[i]);
    return out;
}

Image Film::develop_raw() const {
    return develop(*color_space_by_name("xyz"));  // the identity matrix
}

std::pair<std::uint32_t, std::uint32_t> Film::sample_count_range() const {
    const auto [fewest, most] = std::minmax_element(m_count.begin(), m_count.end());
    return {*fewest, *most};
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
