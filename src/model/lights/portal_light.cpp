// Building a portal light's (u, v) distribution (see portal_light.h).
#include "model/lights/portal_light.h"

#include <stdexcept>
#include <vector>

namespace spt {

namespace {

/// Cells per side of the (u, v) square: as many as the map has rows (lat-long rows span π,
/// as (u, v) does; an equal-area map's side is as fine), within [32, 1024].
int cells_per_side(const EnvironmentMap& map) { return std::clamp(map.height, 32, 1024); }

/// The map's importance density (luminance per steradian, normalised over the sphere) of a
/// world direction: what its own sampling draws from, whatever the light's sampling option.
float importance_density(const EnvironmentMapLight& env, const Vec3& w) {
    const Vec3 d = env.to_map(w);
    const auto [u, v] = env.map->square_of(d);
    return env.map->solid_angle_pdf(env.map->distribution.pdf(u, v), d);
}

/// The midpoint rule's cells per side of (u, v) for power().
constexpr int kPowerCells = 256;

/// A ∫ L̄ cos θ dω over the portal's front, L̄ the mean over 380–780 nm of the arriving
/// radiance, by the midpoint rule over n × n cells of (u, v).
double flux_through(const PortalLight& light, int n) {
    double sum = 0;
    SampledWavelengths lambda = SampledWavelengths::sample(0.5f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float jacobian = 0.f;
            const Vec3 d = light.direction((static_cast<float>(i) + 0.5f) / static_cast<float>(n),
                                           (static_cast<float>(j) + 0.5f) / static_cast<float>(n), jacobian);
            double mean = 0;
            for (int k = 0; k <= 40; k += kLambdaCount) {
                for (int q = 0; q < kLambdaCount; ++q)
                    lambda.lambda[q] = 380.f + 10.f * static_cast<float>(std::min(k + q, 40));
                const SampledSpectrum L = light.arriving(d, lambda);
                for (int q = 0; q < kLambdaCount && k + q <= 40; ++q) mean += L[q];
            }
            sum += mean / 41 * double(dot(d, light.portal().z)) * jacobian;
        }
    return double(light.portal().width) * light.portal().height * sum / (double(n) * n);
}

}  // namespace

PortalLight make_portal_light(const EnvironmentMapLight& environment, const Vec3& origin, const Vec3& edge1,
                              const Vec3& edge2) {
    const float w = length(edge1), h = length(edge2);
    if (!(w > 0.f) || !(h > 0.f) || !std::isfinite(w) || !std::isfinite(h))
        throw std::invalid_argument("an edge of the portal has length 0; expected a rectangle of non-zero area");
    if (!(std::fabs(dot(edge1, edge2)) <= 1e-4f * w * h))
        throw std::invalid_argument("the portal's edges are not perpendicular; expected a rectangle");
    PortalLight light;
    light.environment = environment;
    auto sampling = std::make_shared<PortalSampling>();
    Portal& p = sampling->portal;
    p.origin = origin, p.edge1 = edge1, p.edge2 = edge2;
    p.x = edge1 / w, p.y = edge2 / h, p.z = normalize(cross(p.x, p.y));
    p.width = w, p.height = h;
    light.sampling = sampling;  // direction() below reads the frame through it

    // Each cell: the mean over 2 × 2 points of the density times dω/d(u, v), i.e. the cell's
    // share of the map's importance, with the density floored at 1e-3 of the uniform one.
    const int n = cells_per_side(*environment.map);
    const double floor = 1e-3 / (4 * kPi);
    std::vector<float> weights(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) {
                const float u = (static_cast<float>(i) + 0.25f + 0.5f * static_cast<float>(k & 1)) / static_cast<float>(n);
                const float v = (static_cast<float>(j) + 0.25f + 0.5f * static_cast<float>(k >> 1)) / static_cast<float>(n);
                float jacobian = 0.f;
                const Vec3 d = light.direction(u, v, jacobian);
                sum += (double(importance_density(environment, d)) + floor) * jacobian;
            }
            weights[static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)] =
                static_cast<float>(sum / 4);
        }
    sampling->distribution = WindowedPiecewiseConstant2D(std::move(weights), n, n);
    sampling->power = static_cast<float>(flux_through(light, kPowerCells));
    return light;
}

}  // namespace spt
