#include "model/lights/sun_light.h"

#include <algorithm>

#include "model/lights/sky_light.h"

namespace spt {

std::shared_ptr<const SunModel> make_sun_model(double elevation, double azimuth, double turbidity, double radius) {
    auto m = std::make_shared<SunModel>();
    m->sun = HosekWilkieSun::make(elevation, turbidity);
    m->direction = sun_direction_of(elevation, azimuth);
    const double half = std::sin(0.5 * radius);
    m->one_minus_cos = static_cast<float>(2 * half * half);
    m->chord2 = static_cast<float>(4 * half * half);
    m->inv_sin2 = static_cast<float>(1 / (std::sin(radius) * std::sin(radius)));

    // power(): ∫ over the disc of Σ_c w_c·L_c, by the midpoint rule in 1 − cos γ (the
    // limb darkening's μ is smooth in it).
    const std::array<double, kSkyChannels> mw = sky_channel_mean_weights();
    const int steps = 4000;
    const double width = 2 * half * half;  // 1 − cos r
    double sum = 0;
    for (int i = 0; i < steps; ++i) {
        const double x = width * (i + 0.5) / steps;  // 1 − cos γ
        const double sin2 = x * (2 - x);
        const float mu = static_cast<float>(std::sqrt(std::max(0.0, 1 - sin2 * m->inv_sin2)));
        for (int c = 0; c < kSkyChannels; ++c) sum += mw[static_cast<std::size_t>(c)] * m->sun.radiance(c, mu);
    }
    m->radiant_mean = sum * 2 * 3.141592653589793 * width / steps;
    return m;
}

}  // namespace spt
