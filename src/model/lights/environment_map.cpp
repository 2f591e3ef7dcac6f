// An image's texels → EnvironmentMap: RGB illuminants, the sampling weights and their
// distributions, the integral power() is made of.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include "core/simd.h"
#include "model/lights/environment_map_light.h"
#include "spectral/rgb_texels.h"

namespace spt {

namespace {

/// Luminance Y of linear sRGB (Rec. 709 primaries, D65 white): a texel's spectrum has it.
double luminance(const std::array<float, 3>& rgb) {
    return 0.2126729 * rgb[0] + 0.7151522 * rgb[1] + 0.0721750 * rgb[2];
}

std::string texel_name(int x, int y) { return "texel (" + std::to_string(x) + ", " + std::to_string(y) + ")"; }

/// Solid angle of the patch of the sphere a texel of row y covers (all equal for equal-area).
double texel_solid_angle(const EnvironmentMap& m, int y) {
    if (m.mapping == EnvironmentMapping::equal_area) return 4.0 * std::numbers::pi / (double(m.width) * m.height);
    const double t0 = std::numbers::pi * y / m.height, t1 = std::numbers::pi * (y + 1) / m.height;
    return 2.0 * std::numbers::pi / m.width * (std::cos(t0) - std::cos(t1));
}

/// The mean of a texel's radiance (scale 1) over the 41 wavelengths 380, 390, …, 780 nm, the
/// value of EnvironmentMap::eval at each (on a whole nanometre its D65 interpolation is the
/// tabulated value), four wavelengths at a time with the same float operations per lane.
class SpectralMean {
public:
    explicit SpectralMean(const EnvironmentMap& m) {
        for (int k = 0; k < kPadded; ++k) {
            const float lambda = 380.f + 10.f * static_cast<float>(k);
            m_t[k] = (lambda - 360.f) * (1.f / 470.f);  // SigmoidCoefficients::eval's t
            m_d65[k] = k < kCount ? m.d65[static_cast<std::size_t>(20 + 10 * k)] : 0.f;
        }
    }
    double operator()(const RgbIlluminant& texel) const {
        const Float4 c0 = splat4(texel.shape.c0), c1 = splat4(texel.shape.c1), c2 = splat4(texel.shape.c2);
        const Float4 scale = splat4(texel.scale);
        Double2 low{0.0, 0.0}, high{0.0, 0.0};
        for (int k = 0; k < kPadded; k += 4) {
            const Float4 t = load4(m_t + k);
            const Float4 x = (c0 * t + c1) * t + c2;
            const Float4 s = 0.5f + x / (2.f * sqrt4(1.f + x * x));
            const Float4 value = (scale * s) * load4(m_d65 + k);  // 0 in the padding lanes
            low += low_to_double2(value);
            high += high_to_double2(value);
        }
        return ((low[0] + low[1]) + (high[0] + high[1])) / double(kCount);
    }

private:
    static constexpr int kCount = 41, kPadded = 44;
    float m_t[kPadded], m_d65[kPadded];
};

}  // namespace

std::shared_ptr<const EnvironmentMap> make_environment_map(int width, int height, int channels,
                                                           std::vector<float> values, EnvironmentMapping mapping,
                                                           bool compensated, int threads) {
    if (mapping == EnvironmentMapping::equal_area && width != height)
        throw std::invalid_argument("an equal-area map of " + std::to_string(width) + " x " + std::to_string(height) +
                                    " texels; expected a square image (pbrt-v4's octahedral layout)");
    auto m = std::make_shared<EnvironmentMap>();
    m->width = width, m->height = height, m->mapping = mapping;
    m->d65.resize(471);
    for (int i = 0; i <= 470; ++i) m->d65[static_cast<std::size_t>(i)] = static_cast<float>(d65_unit_luminance(360.0 + i));
    const SpectralMean spectral_mean(*m);
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const std::size_t w = static_cast<std::size_t>(width), stride = static_cast<std::size_t>(channels);
    m->texels.resize(n);
    std::vector<float, NoInitAllocator<float>> weight(n);
    // Per row, summed in row order afterwards (the same for any thread count).
    std::vector<double> row_radiant(static_cast<std::size_t>(height)), row_up(static_cast<std::size_t>(height));
    parallel_rows(height, threads, [&](int y) {
        const bool equirect = mapping == EnvironmentMapping::equirect;
        // Lat-long rows shrink towards the poles: their weight is their share of the sphere.
        const double sin_theta = equirect ? std::sin(std::numbers::pi * (y + 0.5) / height) : 1.0;
        const double omega = texel_solid_angle(*m, y);
        // The cosine to the map's up of the texel's centre (direction_of's): per row for lat-long.
        const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
        const float row_cos_up = equirect ? equirect_to_direction(0.5f, v).y : 0.f;
        std::array<float, 3> previous{-1.f, -1.f, -1.f};
        RgbIlluminant fitted;
        double previous_mean = 0, radiant = 0, up = 0;
        for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
            const float* texel = values.data() + i * stride;
            const std::array<float, 3> rgb =
                channels >= 3 ? std::array<float, 3>{texel[0], texel[1], texel[2]} : std::array<float, 3>{texel[0], texel[0], texel[0]};
            for (float c : rgb) {
                if (!std::isfinite(c))
                    throw std::invalid_argument(texel_name(x, y) + " is " + (std::isnan(c) ? "NaN" : "infinite") +
                                                "; expected finite radiance");
                if (c < 0.f)
                    throw std::invalid_argument(texel_name(x, y) + " is negative (" + std::to_string(c) +
                                                "); expected radiance >= 0");
            }
            // Neighbouring texels are often equal (skies, synthetic maps): fitted once.
            if (rgb != previous) {
                // A grey texel g is g·D65 exactly: the flat shape ½ (all coefficients 0) times 2g.
                fitted = rgb[0] == rgb[1] && rgb[1] == rgb[2] ? RgbIlluminant{{0.f, 0.f, 0.f}, 2.f * rgb[0]} : rgb_illuminant(rgb);
                previous = rgb;
                previous_mean = spectral_mean(fitted);
            }
            m->texels[i] = fitted;
            radiant += previous_mean * omega;
            const double y_lum = luminance(rgb);
            weight[i] = static_cast<float>(y_lum * sin_theta);
            const float cos_up =
                equirect ? row_cos_up
                         : equal_area_square_z((static_cast<float>(x) + 0.5f) / static_cast<float>(width), v);
            if (cos_up > 0) up += y_lum * cos_up * omega;
        }
        row_radiant[static_cast<std::size_t>(y)] = radiant;
        row_up[static_cast<std::size_t>(y)] = up;
    });
    std::vector<float>().swap(values);
    for (int y = 0; y < height; ++y) {
        m->radiant_mean += row_radiant[static_cast<std::size_t>(y)];
        m->up_illuminance += row_up[static_cast<std::size_t>(y)];
    }
    if (!(m->radiant_mean > 0))
        throw std::invalid_argument("every texel is black; expected a map that emits light");
    const std::span<const float> weights(weight.data(), n);
    m->distribution = PiecewiseConstant2D(weights, width, height, threads);
    if (!compensated) return m;
    // Karlík et al. 2019: the weights less their mean, so that what BSDF sampling already
    // finds well (directions no brighter than average) is left to it.
    const double mean = std::accumulate(weight.begin(), weight.end(), 0.0) / static_cast<double>(n);
    std::vector<char> row_any(static_cast<std::size_t>(height), 0);
    parallel_rows(height, threads, [&](int y) {
        bool any = false;
        for (std::size_t i = static_cast<std::size_t>(y) * w, end = i + w; i < end; ++i) {
            weight[i] = static_cast<float>(std::max(0.0, weight[i] - mean));
            any |= weight[i] > 0.f;
        }
        row_any[static_cast<std::size_t>(y)] = any;
    });
    const bool any = std::find(row_any.begin(), row_any.end(), char(1)) != row_any.end();
    m->compensated = any ? PiecewiseConstant2D(weights, width, height, threads) : m->distribution;
    return m;
}

}  // namespace spt
