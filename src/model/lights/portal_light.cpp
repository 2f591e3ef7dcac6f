// Building a portal light's (u, v) distribution (see portal_light.h).
#include "model/lights/portal_light.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "core/parallel_rows.h"

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

/// Points per side of a cell at most (an 8192 × 4096 map: 8 × 8 points in each of 1024² cells).
constexpr int kMostPointsPerSide = 8;

/// The least share of its brightest neighbour's weight a cell is given (below).
constexpr float kNeighbourShare = 0.25f;

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

    // Each cell: the mean over k × k points of the density times dω/d(u, v), i.e. the cell's
    // share of the map's importance, with the density floored at 1e-3 of the uniform one.
    // k puts the points about half a texel apart, so each texel the cell covers in good part
    // holds a point.
    const int n = cells_per_side(*environment.map);
    const int k = std::clamp(2 * ((environment.map->height + n - 1) / n), 2, kMostPointsPerSide);
    const double floor = 1e-3 / (4 * kPi);
    std::vector<float> mean(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    parallel_rows(n, load_threads(), [&](int j) {
        for (int i = 0; i < n; ++i) {
            double sum = 0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const float u = (static_cast<float>(i) + (static_cast<float>(a) + 0.5f) / static_cast<float>(k)) /
                                    static_cast<float>(n);
                    const float v = (static_cast<float>(j) + (static_cast<float>(b) + 0.5f) / static_cast<float>(k)) /
                                    static_cast<float>(n);
                    float jacobian = 0.f;
                    const Vec3 d = light.direction(u, v, jacobian);
                    sum += (double(importance_density(environment, d)) + floor) * jacobian;
                }
            mean[static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)] =
                static_cast<float>(sum / (k * k));
        }
    });
    // A cell may also cover a sliver of a bright texel that none of its points falls in: the
    // edge of a sun. There the radiance is the sun's and, with the cell's mean alone, the
    // density the sky's; a BSDF sample that finds the sun through the sliver would carry the
    // ratio of the two (10^5 for a 1° sun). So a cell weighs at least kNeighbourShare of its
    // brightest neighbour (the sliver's texel lies in a neighbour's points when the cells are
    // about a texel wide or wider). The ratio is then bounded by 1/kNeighbourShare over the
    // neighbour's own share of the texel: a few times the ideal, where it was 10^5
    // (tests/test_portal_light.cpp).
    std::vector<float> weights(mean.size());
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float brightest = 0.f;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int ii = i + di, jj = j + dj;
                    if (ii >= 0 && ii < n && jj >= 0 && jj < n)
                        brightest = std::max(brightest, mean[static_cast<std::size_t>(jj) * n + ii]);
                }
            const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i);
            weights[c] = std::max(mean[c], kNeighbourShare * brightest);
        }
    sampling->distribution = WindowedPiecewiseConstant2D(std::move(weights), n, n);
    sampling->power = static_cast<float>(flux_through(light, kPowerCells));
    return light;
}

}  // namespace spt
