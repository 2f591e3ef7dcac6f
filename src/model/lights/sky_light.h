// The sky of the Hosek–Wilkie model (hosek_wilkie.h) as an infinite light: spectral radiance
// over the upper hemisphere (world +y up), carried to the film at the path's own wavelengths
// (linear between the model's 11 channels, held outside 320–720 nm); nothing below the
// horizon, where the scene's own ground is expected (the ground albedo only shapes the sky).
// The sun's disc is a light of its own (sun_light.h); the sky's radiance includes the
// light scattered towards the view around and in front of the sun.
//
// Sampling (sample_li, sample_le): a PiecewiseConstant2D over the texels of a square mapped
// onto the upper hemisphere without distortion of area (Shirley & Chiu's concentric map onto
// the disc, then Lambert's azimuthal projection onto the hemisphere: every texel the same
// solid angle, 2π/N, so the density in solid angle is the square's over 2π, with no pole to
// resolve), the horizon along the square's edges: no texel reaches below it, where nothing
// arrives. A texel's weight is the sky's luminance at its centre, with a small floor: the
// density need only be positive wherever the sky is; pdf_li reads the table sample_li draws
// from, so MIS weights are exact.
//
// Light subpaths: as the other infinite lights, a point on the disk of the scene's bounding
// sphere facing the sampled direction, one radius upstream.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include "core/piecewise_constant.h"
#include "model/lights/bounding_disk.h"
#include "model/lights/hosek_wilkie.h"
#include "model/lights/light_sample.h"

namespace spt {

/// What a sky keeps (shared by the copies of its light).
struct SkyModel {
    HosekWilkieSky sky;
    Vec3 sun_direction{0, 1, 0};      ///< unit, world space
    PiecewiseConstant2D distribution; ///< over the hemisphere's square (map +z = world +y)
    int resolution = 0;               ///< texels per side of the square
    /// ∫ over the sphere of the radiance's mean over 380–780 nm (scale 1): power() / (πR²).
    double radiant_mean = 0;

    /// Radiance of channel c along the unit world direction d (0 below the horizon).
    float channel_radiance(int c, const Vec3& d) const {
        if (!(d.y >= 0.f)) return 0.f;
        const float cos_gamma = std::clamp(dot(d, sun_direction), -1.f, 1.f);
        // γ from sine and cosine: acos loses the small angles next to the sun.
        const float gamma = std::atan2(length(cross(d, sun_direction)), cos_gamma);
        return sky.radiance(c, d.y, gamma, cos_gamma);
    }

    static Vec3 map_of(const Vec3& w) { return {w.x, -w.z, w.y}; }
    static Vec3 world_of(const Vec3& m) { return {m.x, m.z, -m.y}; }

    /// A direction drawn from the table (world space), or none.
    std::optional<Vec3> sample_direction(float u1, float u2) const;
    /// Solid-angle density of sample_direction's direction d (unit, world space).
    float direction_pdf(const Vec3& d) const;
};

/// The unit direction (z ≥ 0) of the point (u, v) ∈ [0, 1]² of the hemisphere's square.
Vec3 square_to_hemisphere(float u, float v);
/// Its inverse, for a unit direction with z ≥ 0.
std::array<float, 2> hemisphere_to_square(const Vec3& d);

/// elevation and azimuth in radians (the sun at (cos η·cos φ, sin η, cos η·sin φ): azimuth 0
/// towards +x, 90° towards +z), turbidity in [1, 10], albedo in [0, 1]; `resolution` texels
/// per side of the sampling table.
std::shared_ptr<const SkyModel> make_sky_model(double elevation, double azimuth, double turbidity, double albedo,
                                               int resolution = 256);

/// The unit direction towards a sun at this elevation and azimuth (radians).
Vec3 sun_direction_of(double elevation, double azimuth);

struct SkyLight {
    std::shared_ptr<const SkyModel> model;
    float scale = 1.f;
    Vec3 center;  ///< the scene's bounding sphere (light subpaths' disk)
    float radius = 1.f;

    static constexpr LightType type = LightType::infinite;

    float power() const { return static_cast<float>(kPi * radius * radius * scale * model->radiant_mean); }
    /// Flat: the radiance's spectrum varies over the sky (light.h).
    float spectral_power(float /*lambda_nm*/) const { return power(); }

    /// Radiance arriving along an escaped ray of direction d (unit).
    SampledSpectrum arriving(const Vec3& d, const SampledWavelengths& lambda) const {
        SampledSpectrum L;
        if (!(d.y >= 0.f)) return L;
        float channel[kSkyChannels];
        unsigned done = 0;
        const auto value = [&](int c) {
            if (!((done >> c) & 1u)) {
                channel[c] = model->channel_radiance(c, d);
                done |= 1u << c;
            }
            return channel[c];
        };
        for (int k = 0; k < kLambdaCount; ++k) {
            const SkyChannelLerp l = sky_channel_lerp(lambda.lambda[k]);
            float v = (1.f - l.upper_weight) * value(l.lower);
            if (l.upper_weight > 0.f) v += l.upper_weight * value(l.lower + 1);
            L[k] = scale * v;
        }
        return L;
    }

    float pdf_li(const LightSampleContext& /*ctx*/, const Vec3& wi) const { return direction_pdf(wi); }

    bool sample_li(const LightSampleContext& /*ctx*/, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const std::optional<Vec3> d = sample_direction(u1, u2);
        if (!d) return false;
        ls.wi = *d;
        ls.pdf = direction_pdf(ls.wi);
        if (!(ls.pdf > 0.f) || !std::isfinite(ls.pdf)) return false;
        ls.L = arriving(ls.wi, lambda);
        ls.infinite = true;
        return true;
    }

    /// Origin of a light subpath: a direction towards the sky by the table, then a point on
    /// the disk of radius R facing it, one radius upstream; the ray travels along o.w.
    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float u3, float u4, float /*time*/) const {
        const std::optional<Vec3> towards = sample_direction(u1, u2);
        if (!towards) return std::nullopt;
        LightOrigin o;
        o.infinite = true;
        o.w = -*towards;
        o.pdf_dir = direction_pdf(*towards);
        if (!(o.pdf_dir > 0.f) || !std::isfinite(o.pdf_dir)) return std::nullopt;
        place_on_bounding_disk(o, center, radius, u3, u4);
        o.Le = arriving(*towards, lambda);
        return o;
    }
    /// Solid-angle density of sample_le's direction w (the light arrives from −w).
    float pdf_le_dir(const Vec3& /*n*/, const Vec3& w) const { return direction_pdf(-w); }
    /// Planar density of the disk point through which a ray along d (unit) reaches p.
    float pdf_le_pos(const Vec3& p, const Vec3& d) const {
        return bounding_disk_pdf_pos(center, radius, p, d);
    }

private:
    std::optional<Vec3> sample_direction(float u1, float u2) const { return model->sample_direction(u1, u2); }
    float direction_pdf(const Vec3& towards) const { return model->direction_pdf(towards); }
};

}  // namespace spt
