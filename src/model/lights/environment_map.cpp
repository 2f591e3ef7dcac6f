// An image's texels → EnvironmentMap: RGB illuminants, the sampling weights and their
// distributions, the integral power() is made of.
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

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

}  // namespace

std::shared_ptr<const EnvironmentMap> make_environment_map(int width, int height, int channels,
                                                           const std::vector<float>& values,
                                                           EnvironmentMapping mapping, bool compensated) {
    if (mapping == EnvironmentMapping::equal_area && width != height)
        throw std::invalid_argument("an equal-area map of " + std::to_string(width) + " x " + std::to_string(height) +
                                    " texels; expected a square image (pbrt-v4's octahedral layout)");
    auto m = std::make_shared<EnvironmentMap>();
    m->width = width, m->height = height, m->mapping = mapping;
    m->d65.resize(471);
    for (int i = 0; i <= 470; ++i) m->d65[static_cast<std::size_t>(i)] = static_cast<float>(d65_unit_luminance(360.0 + i));
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    m->texels.resize(n);
    std::vector<float> weight(n);
    std::array<float, 3> previous{-1.f, -1.f, -1.f};
    RgbIlluminant fitted;
    double previous_mean = 0;
    for (int y = 0; y < height; ++y) {
        // Lat-long rows shrink towards the poles: their weight is their share of the sphere.
        const double sin_theta =
            mapping == EnvironmentMapping::equirect ? std::sin(std::numbers::pi * (y + 0.5) / height) : 1.0;
        const double omega = texel_solid_angle(*m, y);
        for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
            std::array<float, 3> rgb;
            for (int c = 0; c < 3; ++c) rgb[static_cast<std::size_t>(c)] = values[i * static_cast<std::size_t>(channels) + (channels >= 3 ? static_cast<std::size_t>(c) : 0)];
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
                double sum = 0;
                for (int k = 0; k <= 40; ++k) sum += m->eval(fitted, 380.f + 10.f * static_cast<float>(k));
                previous_mean = sum / 41.0;
            }
            m->texels[i] = fitted;
            m->radiant_mean += previous_mean * omega;
            weight[i] = static_cast<float>(luminance(rgb) * sin_theta);
            const Vec3 d = m->direction_of((static_cast<float>(x) + 0.5f) / static_cast<float>(width),
                                           (static_cast<float>(y) + 0.5f) / static_cast<float>(height));
            const double cos_up = mapping == EnvironmentMapping::equal_area ? d.z : d.y;
            if (cos_up > 0) m->up_illuminance += luminance(rgb) * cos_up * omega;
        }
    }
    if (!(m->radiant_mean > 0))
        throw std::invalid_argument("every texel is black; expected a map that emits light");
    m->distribution = PiecewiseConstant2D(weight, width, height);
    if (!compensated) return m;
    // Karlík et al. 2019: the weights less their mean, so that what BSDF sampling already
    // finds well (directions no brighter than average) is left to it.
    const double mean = std::accumulate(weight.begin(), weight.end(), 0.0) / static_cast<double>(n);
    bool any = false;
    for (float& w : weight) {
        w = static_cast<float>(std::max(0.0, w - mean));
        any |= w > 0.f;
    }
    m->compensated = any ? PiecewiseConstant2D(weight, width, height) : m->distribution;
    return m;
}

}  // namespace spt
