// The sun of the Hosek–Wilkie model (hosek_wilkie.h) as an infinite light: a disc of angular
// radius r about the sun's direction, its radiance the 2013 solar radiance function at the
// sun's elevation (the centre's; the disc spans ±r of elevation, which the function barely
// changes over) times the limb darkening at the point of the disc seen, at the path's
// wavelengths (linear between channels, held outside 320–720 nm). Nothing arrives from
// outside the disc.
//
// r defaults to 0.2665°: the IAU 2015 nominal solar radius (695 700 km) seen from one
// astronomical unit (149 597 870.7 km), asin(R/au). (The model's sample code uses 0.255°;
// its radiance is per steradian, so the radius only sets the disc's solid angle.)
//
// Sampling: directions uniform over the disc's cone, density 1/(2π(1 − cos r)) in solid
// angle; 1 − cos r and the test whether a direction is on the disc are formed from chord
// lengths (|d − s|² = 2(1 − cos γ)), which keep their precision for a disc a few thousandths
// of a radian across, where cosines near 1 in float do not.
//
// Light subpaths: as the other infinite lights, a point on the disk of the scene's bounding
// sphere facing a direction sampled from the cone, one radius upstream.
#pragma once
#include <cmath>
#include <memory>
#include <optional>

#include "core/frame.h"
#include "model/lights/bounding_disk.h"
#include "model/lights/hosek_wilkie.h"
#include "model/lights/light_sample.h"

namespace spt {

inline constexpr double kSunAngularRadiusDegrees = 0.2665;

/// What a sun keeps (shared by the copies of its light).
struct SunModel {
    HosekWilkieSun sun;
    Vec3 direction{0, 1, 0};   ///< unit, world space: towards the disc's centre
    float one_minus_cos = 0;   ///< 1 − cos r
    float chord2 = 0;          ///< |d − direction|² on the rim: 2(1 − cos r)
    float inv_sin2 = 0;        ///< 1 / sin² r
    double radiant_mean = 0;   ///< ∫ over the disc of the radiance's mean over 380–780 nm (scale 1)
};

/// A sun at this elevation and azimuth (radians; as make_sky_model), turbidity in [1, 10],
/// of angular radius `radius` (radians).
std::shared_ptr<const SunModel> make_sun_model(double elevation, double azimuth, double turbidity,
                                               double radius = kSunAngularRadiusDegrees * 3.141592653589793 / 180.0);

struct SunLight {
    std::shared_ptr<const SunModel> model;
    float scale = 1.f;
    Vec3 center;  ///< the scene's bounding sphere (light subpaths' disk)
    float radius = 1.f;

    static constexpr LightType type = LightType::infinite;

    float power() const { return static_cast<float>(kPi * radius * radius * scale * model->radiant_mean); }
    /// Flat: the radiance's spectrum varies over the disc (light.h).
    float spectral_power(float /*lambda_nm*/) const { return power(); }

    /// Radiance arriving along an escaped ray of direction d (unit): the disc's, 0 off it.
    SampledSpectrum arriving(const Vec3& d, const SampledWavelengths& lambda) const {
        SampledSpectrum L;
        const SunModel& m = *model;
        if (!on_disc(d)) return L;
        const float mu = std::sqrt(std::max(0.f, 1.f - length_squared(cross(d, m.direction)) * m.inv_sin2));
        for (int k = 0; k < kLambdaCount; ++k) {
            const SkyChannelLerp l = sky_channel_lerp(lambda.lambda[k]);
            float v = (1.f - l.upper_weight) * m.sun.radiance(l.lower, mu);
            if (l.upper_weight > 0.f) v += l.upper_weight * m.sun.radiance(l.lower + 1, mu);
            L[k] = scale * v;
        }
        return L;
    }

    float pdf_li(const LightSampleContext& /*ctx*/, const Vec3& wi) const { return on_disc(wi) ? cone_pdf() : 0.f; }

    bool sample_li(const LightSampleContext& /*ctx*/, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const std::optional<Vec3> d = sample_direction(u1, u2);
        if (!d) return false;
        ls.wi = *d;
        ls.pdf = cone_pdf();
        ls.L = arriving(ls.wi, lambda);
        ls.infinite = true;
        return true;
    }

    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float u3, float u4, float /*time*/) const {
        const std::optional<Vec3> towards = sample_direction(u1, u2);
        if (!towards) return std::nullopt;
        LightOrigin o;
        o.infinite = true;
        o.w = -*towards;
        o.pdf_dir = cone_pdf();
        place_on_bounding_disk(o, center, radius, u3, u4);
        o.Le = arriving(*towards, lambda);
        return o;
    }
    /// Solid-angle density of sample_le's direction w (the light arrives from −w).
    float pdf_le_dir(const Vec3& /*n*/, const Vec3& w) const { return on_disc(-w) ? cone_pdf() : 0.f; }
    /// Planar density of the disk point through which a ray along d (unit) reaches p.
    float pdf_le_pos(const Vec3& p, const Vec3& d) const {
        return bounding_disk_pdf_pos(center, radius, p, d);
    }

    bool on_disc(const Vec3& d) const { return length_squared(d - model->direction) <= model->chord2; }

private:
    float cone_pdf() const { return 1.f / (2.f * kPi * model->one_minus_cos); }
    /// A direction uniform over the cone (1 − cos θ uniform in [0, 1 − cos r]); none when
    /// rounding puts it just off the disc (its density would be 0).
    std::optional<Vec3> sample_direction(float u1, float u2) const {
        const float x = u1 * model->one_minus_cos;  // 1 − cos θ
        const float sin_theta = std::sqrt(std::max(0.f, x * (2.f - x)));
        const float phi = 2.f * kPi * u2;
        const Vec3 d = normalize(Frame(model->direction).to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1.f - x}));
        if (!on_disc(d)) return std::nullopt;
        return d;
    }
};

}  // namespace spt
