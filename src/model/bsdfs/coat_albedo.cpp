#include "model/bsdfs/coat_albedo.h"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>

#include "model/bsdfs/fresnel.h"
#include "model/bsdfs/microfacet.h"

namespace spt {

namespace {

/// Directional albedo of the coat's specular lobe at cos θo = mu.
double coat_directional_albedo(const GgxDistribution& ggx, float eta, float mu) {
    mu = std::max(mu, 1e-4f);
    if (ggx.is_smooth()) return fresnel_dielectric(mu, eta);
    const Vec3 o{std::sqrt(std::max(0.f, 1.f - mu * mu)), 0.f, mu};
    constexpr int kSide = 64;
    double sum = 0;
    for (int a = 0; a < kSide; ++a)
        for (int b = 0; b < kSide; ++b) {
            const Vec3 m = ggx.sample_visible_normal(o, (a + 0.5f) / kSide, (b + 0.5f) / kSide);
            const float om = dot(o, m);
            const Vec3 i = m * (2.f * om) - o;
            if (!(i.z > 0.f) || !(om > 0.f)) continue;
            sum += fresnel_dielectric(om, eta) * ggx.G2(o, i) / ggx.G1(o);
        }
    return sum / (kSide * kSide);
}

}  // namespace

CoatAlbedo make_coat_albedo(float alpha, float eta) {
    CoatAlbedo c;
    const GgxDistribution ggx{alpha};
    constexpr int N = CoatAlbedo::kPoints;
    for (int j = 0; j < N; ++j)
        c.e[static_cast<std::size_t>(j)] = static_cast<float>(coat_directional_albedo(ggx, eta, float(j) / (N - 1)));
    // E_avg = 2∫E(μ)μ dμ of the piecewise-linear E, exactly: on [a, b] with E from ea to eb,
    // ∫μE dμ = h·(ea·(2a + b) + eb·(a + 2b))/6.
    double avg = 0;
    for (std::size_t j = 0; j + 1 < N; ++j) {
        const double a = double(j) / (N - 1), b = double(j + 1) / (N - 1), h = b - a;
        avg += 2.0 * h * (c.e[j] * (2 * a + b) + c.e[j + 1] * (a + 2 * b)) / 6.0;
    }
    c.average = static_cast<float>(avg);
    return c;
}

const CoatAlbedoRows& coat_albedo_table(float eta) {
    static std::mutex mutex;
    static std::map<float, std::unique_ptr<const CoatAlbedoRows>> tables;
    const std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<const CoatAlbedoRows>& slot = tables[eta];
    if (!slot) {
        auto t = std::make_unique<CoatAlbedoRows>();
        t->first = 0.f, t->last = 1.f, t->rows_per_unit = kCoatRoughnessRows - 1;
        for (int i = 0; i < kCoatRoughnessRows; ++i)
            t->rows.push_back(make_coat_albedo(static_cast<float>(i) / (kCoatRoughnessRows - 1), eta));
        slot = std::move(t);
    }
    return *slot;
}

const CoatAlbedoRows& coat_albedo_over_index(float alpha, float eta_min, float eta_max) {
    static std::mutex mutex;
    static std::map<std::tuple<float, float, float>, std::unique_ptr<const CoatAlbedoRows>> tables;
    const std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<const CoatAlbedoRows>& slot = tables[{alpha, eta_min, eta_max}];
    if (!slot) {
        auto t = std::make_unique<CoatAlbedoRows>();
        t->first = eta_min, t->last = eta_max;
        const double range = double(eta_max) - eta_min;
        // Intervals: enough for kCoatIndexStep, at least one (two rows: at() reads a pair).
        const int intervals = std::clamp(static_cast<int>(std::ceil(range / kCoatIndexStep - 1e-6)), 1,
                                         kCoatMaxIndexRows - 1);
        t->rows_per_unit = range > 0 ? static_cast<float>(intervals / range) : 0.f;
        for (int r = 0; r <= intervals; ++r)
            t->rows.push_back(make_coat_albedo(alpha, static_cast<float>(eta_min + range * r / intervals)));
        slot = std::move(t);
    }
    return *slot;
}

}  // namespace spt
