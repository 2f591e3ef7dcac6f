#include "model/lights/sky_light.h"

#include <algorithm>
#include <vector>

namespace spt {

Vec3 square_to_hemisphere(float u, float v) {
    // Concentric map onto the unit disc (Shirley & Chiu 1997), radius ρ and angle φ.
    const float a = 2.f * u - 1.f, b = 2.f * v - 1.f;
    float rho = 0.f, phi = 0.f;
    if (std::fabs(a) >= std::fabs(b)) {
        rho = a;
        phi = a != 0.f ? (kPi / 4.f) * (b / a) : 0.f;
    } else {
        rho = b;
        phi = kPi / 2.f - (kPi / 4.f) * (a / b);
    }
    // Lambert's projection: z = 1 − ρ², the horizontal radius ρ·√(2 − ρ²).
    const float s = rho * std::sqrt(std::max(0.f, 2.f - rho * rho));
    return {s * std::cos(phi), s * std::sin(phi), std::max(0.f, 1.f - rho * rho)};
}

std::array<float, 2> hemisphere_to_square(const Vec3& d) {
    // ρ² = 1 − z, formed without cancellation near the pole; the disc point p = d_xy/√(2 − ρ²).
    const float horizontal2 = d.x * d.x + d.y * d.y;
    const float rho2 = d.z > 0.5f ? horizontal2 / (1.f + d.z) : 1.f - d.z;
    const float rho = std::sqrt(std::max(0.f, rho2));
    const float k = 1.f / std::sqrt(std::max(1.f, 2.f - rho2));
    const float px = d.x * k, py = d.y * k;
    float a = 0.f, b = 0.f;
    if (std::fabs(px) >= std::fabs(py)) {
        a = std::copysign(rho, px);
        b = px != 0.f ? a * std::atan(py / px) / (kPi / 4.f) : 0.f;
    } else {
        b = std::copysign(rho, py);
        const float s = py > 0.f ? 1.f : -1.f;  // φ of b·(cos φ, sin φ) lies in [π/4, 3π/4]
        a = b * (kPi / 2.f - std::atan2(s * py, s * px)) / (kPi / 4.f);
    }
    return {std::clamp(0.5f * (a + 1.f), 0.f, 1.f), std::clamp(0.5f * (b + 1.f), 0.f, 1.f)};
}

std::optional<Vec3> SkyModel::sample_direction(float u1, float u2) const {
    float square_pdf = 0.f;
    const auto [u, v] = distribution.sample(u1, u2, &square_pdf);
    if (!(square_pdf > 0.f)) return std::nullopt;
    const Vec3 d = normalize(world_of(square_to_hemisphere(u, v)));
    if (!(d.y >= 0.f)) return std::nullopt;
    return d;
}

float SkyModel::direction_pdf(const Vec3& d) const {
    if (!(d.y >= 0.f)) return 0.f;
    const auto [u, v] = hemisphere_to_square(map_of(d));
    return distribution.pdf(u, v) * (0.5f * kInvPi);
}

Vec3 sun_direction_of(double elevation, double azimuth) {
    const double ce = std::cos(elevation);
    return normalize(Vec3(static_cast<float>(ce * std::cos(azimuth)), static_cast<float>(std::sin(elevation)),
                          static_cast<float>(ce * std::sin(azimuth))));
}

std::shared_ptr<const SkyModel> make_sky_model(double elevation, double azimuth, double turbidity, double albedo,
                                               int resolution) {
    auto m = std::make_shared<SkyModel>();
    m->sky = HosekWilkieSky::make(elevation, turbidity, albedo);
    m->sun_direction = sun_direction_of(elevation, azimuth);
    m->resolution = resolution;

    // Sampling weights: the luminance at each texel's centre, moved up onto the horizon
    // where the horizon crosses the texel (a corner above it); 0 below.
    const std::array<double, kSkyChannels> yw = sky_channel_luminance_weights();
    const auto luminance = [&](const Vec3& d) {
        double y = 0;
        for (int c = 0; c < kSkyChannels; ++c)
            if (yw[static_cast<std::size_t>(c)] > 0) y += yw[static_cast<std::size_t>(c)] * m->channel_radiance(c, d);
        return y;
    };
    const int n = resolution;
    std::vector<float> weight(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.f);
    double weight_sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3 d = SkyModel::world_of(square_to_hemisphere((static_cast<float>(i) + 0.5f) / static_cast<float>(n),
                                                                   (static_cast<float>(j) + 0.5f) / static_cast<float>(n)));
            const float w = static_cast<float>(luminance(d));
            weight[static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)] = w;
            weight_sum += w;
        }
    // A floor (10⁻³ of the mean) for texels whose fitted radiance rounds to 0: the density
    // must stay positive wherever the sky may shine.
    const float floor = static_cast<float>(1e-3 * weight_sum / static_cast<double>(weight.size()));
    for (float& w : weight) w = std::max(w, floor);
    m->distribution = PiecewiseConstant2D(weight, n, n);

    // power(): the mean over 380–780 nm integrated over the upper hemisphere by the midpoint
    // rule on a grid uniform in solid angle (cos θ × φ).
    const std::array<double, kSkyChannels> mw = sky_channel_mean_weights();
    const int nc = 400, np = 800;
    double sum = 0;
    for (int a = 0; a < nc; ++a) {
        const double c = (a + 0.5) / nc, s = std::sqrt(1 - c * c);
        for (int b = 0; b < np; ++b) {
            const double phi = 2 * 3.141592653589793 * (b + 0.5) / np;
            const Vec3 d(static_cast<float>(s * std::cos(phi)), static_cast<float>(c), static_cast<float>(s * std::sin(phi)));
            for (int ch = 0; ch < kSkyChannels; ++ch)
                if (mw[static_cast<std::size_t>(ch)] > 0) sum += mw[static_cast<std::size_t>(ch)] * m->channel_radiance(ch, d);
        }
    }
    m->radiant_mean = sum * 2 * 3.141592653589793 / (static_cast<double>(nc) * np);
    return m;
}

}  // namespace spt
