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
      m_exact(4 * static_cast<std::size_t>(width) * height),
      m_count(static_cast<std::size_t>(width) * height, 0) {}

std::array<double, 4> Film::pixel_sums(std::size_t i) const {
    const ExactSum* e = &m_exact[4 * i];
    return {e[0].value() + m_xyz[3 * i], e[1].value() + m_xyz[3 * i + 1], e[2].value() + m_xyz[3 * i + 2],
            e[3].value() + m_y_squared[i]};
}

std::array<double, 4> Film::pixel_splat_sums(std::size_t i) const {
    const ExactSum* e = &m_exact_splats[4 * i];
    return {e[0].value() + m_splat_xyz[3 * i], e[1].value() + m_splat_xyz[3 * i + 1],
            e[2].value() + m_splat_xyz[3 * i + 2], e[3].value() + m_splat_y_squared[i]};
}

std::vector<double> Film::xyz_sums() const {
    std::vector<double> out(m_xyz.size());
    for (std::size_t i = 0; i < m_count.size(); ++i) {
        const auto s = pixel_sums(i);
        out[3 * i] = s[0], out[3 * i + 1] = s[1], out[3 * i + 2] = s[2];
    }
    return out;
}

void Film::fold_pixel(int x, int y) {
    const std::size_t i = index(x, y);
    ExactSum* e = &m_exact[4 * i];
    for (int c = 0; c < 3; ++c) e[c].add(m_xyz[3 * i + c]), m_xyz[3 * i + c] = 0.0;
    e[3].add(m_y_squared[i]), m_y_squared[i] = 0.0;
}

void Film::fold_splats() {
    for (std::size_t i = 0; i < m_splat_y_squared.size(); ++i) {
        ExactSum* e = &m_exact_splats[4 * i];
        for (int c = 0; c < 3; ++c) e[c].add(m_splat_xyz[3 * i + c]), m_splat_xyz[3 * i + c] = 0.0;
        e[3].add(m_splat_y_squared[i]), m_splat_y_squared[i] = 0.0;
    }
}

bool Film::is_folded() const {
    const auto zero = [](const std::vector<double>& v) {
        return std::all_of(v.begin(), v.end(), [](double d) { return d == 0.0; });
    };
    return zero(m_xyz) && zero(m_y_squared) && zero(m_splat_xyz) && zero(m_splat_y_squared);
}

void Film::merge(const Film& part) {
    for (std::size_t i = 0; i < m_exact.size(); ++i) m_exact[i].add(part.m_exact[i]);
    for (std::size_t i = 0; i < m_count.size(); ++i) m_count[i] += part.m_count[i];
    if (part.has_splats()) {
        if (!has_splats()) allocate_splats();
        for (std::size_t i = 0; i < m_exact_splats.size(); ++i) m_exact_splats[i].add(part.m_exact_splats[i]);
        m_light_paths += part.m_light_paths;
    }
    m_rejected_nonfinite += part.rejected_nonfinite();
    m_rejected_negative += part.rejected_negative();
}

Xyz Film::pixel_xyz(int x, int y) const {
    const std::size_t i = index(x, y);
    Xyz c;
    if (m_count[i] > 0) {
        const double inv = 1.0 / m_count[i];
        const auto s = pixel_sums(i);
        c = {s[0] * inv, s[1] * inv, s[2] * inv};
    }
    if (const double m = light_paths_per_pixel(); m > 0 && !m_splat_xyz.empty()) {
        const double inv = 1.0 / m;
        const auto s = pixel_splat_sums(i);
        c.x += s[0] * inv, c.y += s[1] * inv, c.z += s[2] * inv;
    }
    return c;
}

double Film::pixel_y_standard_error(int x, int y) const {
    const std::size_t i = index(x, y);
    const double n = m_count[i];
    if (n < 2) return 0.0;
    const auto s = pixel_sums(i);
    const double mean = s[1] / n;
    const double variance = std::max(0.0, (s[3] / n - mean * mean) * n / (n - 1));
    // Splats: each light path adds c_k to this pixel (mostly 0), so the variance of Σc_k/M is
    // about Σc_k²/M² (the splats' squares; their mean is negligible next to them per path).
    double splat_variance = 0.0;
    if (const double m = light_paths_per_pixel(); m > 0 && !m_splat_y_squared.empty())
        splat_variance = pixel_splat_sums(i)[3] / (m * m);
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
    append_array(out, m_exact);
    if (has_splats()) {  // bdpt and vcm films only
        out.append(reinterpret_cast<const char*>(&m_light_paths), sizeof m_light_paths);
        append_array(out, m_splat_xyz);
        append_array(out, m_splat_y_squared);
        append_array(out, m_exact_splats);
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
    read_array(in, m_exact);
    if (!in.empty()) {
        if (in.size() < sizeof m_light_paths) throw std::runtime_error("film state is truncated");
        std::memcpy(&m_light_paths, in.data(), sizeof m_light_paths);
        in.remove_prefix(sizeof m_light_paths);
        allocate_splats();
        read_array(in, m_splat_xyz);
        read_array(in, m_splat_y_squared);
        read_array(in, m_exact_splats);
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
