// An environment map: radiance arriving from every direction, read from an HDR image, either
// equirectangular (lat-long; Mitsuba 3's convention: +y up, u = atan2(x, −z)/2π, v = θ/π from
// the top row) or pbrt-v4's equal-area octahedral square (+z up in the map's space), turned
// by a rotation (`world_from_map`) and multiplied by `scale`.
//
// Look-up: the nearest texel (as pbrt-v4's ImageInfiniteLight), so the radiance is constant
// over each texel's patch of the sphere and the sampling density below, constant over the
// same patch (up to the lat-long Jacobian), is exactly proportional to a per-texel weight:
// nothing the filter spreads lies outside the patch the distribution gives weight to.
// Texels: RGB illuminants (spectral/rgb_sigmoid_table.h: scale · s(λ) · D65 of luminance 1),
// evaluated exactly at the path's wavelengths; a white texel is D65, and a texel's radiance
// has the XYZ of its linear sRGB colour (the rule of emission textures).
//
// Sampling (sample_li): a PiecewiseConstant2D over the texels of their luminance (times
// sin θ at the texel's centre for lat-long, whose rows shrink towards the poles; equal-area
// texels all cover 4π/N steradians), converted to solid angle by the mapping's Jacobian
// (lat-long 1/(2π² sin θ), equal-area 1/(4π)). Options: uniform directions over the sphere
// (the baseline importance sampling is measured against), and the MIS-compensated density
// of Karlík et al. 2019 (the weights less their mean, clamped at 0: directions no brighter
// than average are left to BSDF sampling). The compensated density is 0 there, which is
// right only where BSDF sampling is combined with it by MIS (the default of every
// integrator); with light sampling alone (`--light-sampling light`) those directions would
// stay dark. sample_le always uses the full density (light subpaths have no other strategy
// for their first direction).
//
// Light subpaths: as the constant environment (environment_light.h), a point on the disk of
// the scene's bounding sphere facing the sampled direction, one radius upstream.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "core/no_init_allocator.h"
#include "core/parallel_rows.h"
#include "core/piecewise_constant.h"
#include "core/sampling.h"
#include "core/simd.h"
#include "geometry/sphere_mappings.h"
#include "model/lights/bounding_disk.h"
#include "model/lights/light_sample.h"
#include "spectral/rgb_sigmoid_table.h"

namespace spt {

enum class EnvironmentMapping { equirect, equal_area };
enum class EnvironmentSampling { importance, uniform };

/// What an environment map keeps (shared by the copies of its light): the texels as RGB
/// illuminants, D65 of unit luminance tabulated at 1 nm, and the sampling distributions.
struct EnvironmentMap {
    int width = 0, height = 0;
    EnvironmentMapping mapping = EnvironmentMapping::equirect;
    std::vector<RgbIlluminant, NoInitAllocator<RgbIlluminant>> texels;  ///< row-major, row 0 = the top of the image
    std::vector<float> d65;             ///< at 360, 361, …, 830 nm
    PiecewiseConstant2D distribution;   ///< over the unit square of the mapping, all texels
    /// The same less the mean weight (Karlík et al. 2019); built only for lights that use it.
    PiecewiseConstant2D compensated;
    /// ∫ over the sphere of the radiance's mean over 380–780 nm (scale 1): power() / (πR²).
    double radiant_mean = 0;
    /// The illuminance (scale 1) on a surface facing the map's up (+y of lat-long, +z of
    /// equal-area) from the texels whose centre lies above its horizon.
    double up_illuminance = 0;

    /// The texel's spectrum at the path's wavelengths (scale 1), the four at once: the sigmoid
    /// of SigmoidCoefficients::eval times D65 interpolated linearly between whole nanometres.
    Float4 eval(const RgbIlluminant& t, const SampledWavelengths& lambda) const {
        Float4 l, d;
        std::memcpy(&l, lambda.lambda.data(), sizeof l);
        const Float4 x = min4(max4(l - 360.f, splat4(0.f)), splat4(469.999f));
        const Int4 i = to_int4(x);
        const Float4 f = x - to_float4(i);
        for (int k = 0; k < kLambdaCount; ++k) {
            const std::size_t j = static_cast<std::size_t>(i[k]);
            d[k] = d65[j] * (1.f - f[k]) + d65[j + 1] * f[k];
        }
        const Float4 tt = (l - 360.f) * (1.f / 470.f);
        const Float4 s = (splat4(t.shape.c0) * tt + t.shape.c1) * tt + t.shape.c2;
        return t.scale * (0.5f + s / (2.f * sqrt4(1.f + s * s))) * d;
    }
    /// The square's point (u, v) ∈ [0, 1)² of a direction in the map's space.
    std::array<float, 2> square_of(const Vec3& d) const {
        if (mapping == EnvironmentMapping::equal_area) {
            const auto [u, v] = equal_area_sphere_to_square(d);
            return {u, v};
        }
        const auto [u, v] = direction_to_equirect(d);
        return {u, v};
    }
    Vec3 direction_of(float u, float v) const {
        return mapping == EnvironmentMapping::equal_area ? equal_area_square_to_sphere(u, v)
                                                         : equirect_to_direction(u, v);
    }
    /// The nearest texel to the square's point.
    const RgbIlluminant& texel_at(float u, float v) const {
        const int x = std::clamp(static_cast<int>(u * static_cast<float>(width)), 0, width - 1);
        const int y = std::clamp(static_cast<int>(v * static_cast<float>(height)), 0, height - 1);
        return texels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
    }
    /// The square density turned into solid angle at the direction d (map space, unit).
    /// Lat-long: 1/(2π² sin θ), with sin θ from d's own components rather than from v, which
    /// rounds to the pole (sin θ = 0) for directions within 1e-4 of it.
    float solid_angle_pdf(float square_pdf, const Vec3& d) const {
        if (mapping == EnvironmentMapping::equal_area) return square_pdf * (0.25f * kInvPi);
        const float sin_theta = std::sqrt(d.x * d.x + d.z * d.z);
        return sin_theta > 0.f ? square_pdf / (2.f * kPi * kPi * sin_theta) : 0.f;
    }
};

struct EnvironmentMapLight {
    std::shared_ptr<const EnvironmentMap> map;
    /// Rows of the rotation from the map's space to the world (orthonormal; a mirror allowed).
    Vec3 world_from_map[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    float scale = 1.f;
    EnvironmentSampling sampling = EnvironmentSampling::importance;
    bool mis_compensation = false;
    Vec3 center;          ///< the scene's bounding sphere (light subpaths' disk)
    float radius = 1.f;

    static constexpr LightType type = LightType::infinite;

    Vec3 to_world(const Vec3& m) const {
        return {dot(world_from_map[0], m), dot(world_from_map[1], m), dot(world_from_map[2], m)};
    }
    Vec3 to_map(const Vec3& w) const {
        return world_from_map[0] * w.x + world_from_map[1] * w.y + world_from_map[2] * w.z;
    }

    float power() const { return static_cast<float>(kPi * radius * radius * scale * map->radiant_mean); }
    /// Flat: the radiance's spectrum varies over the map (light.h).
    float spectral_power(float /*lambda_nm*/) const { return power(); }

    /// Radiance arriving along an escaped ray of direction d (unit): the nearest texel's.
    SampledSpectrum arriving(const Vec3& d, const SampledWavelengths& lambda) const {
        return radiance(look_up(d).texel, lambda);
    }

    /// Solid-angle density of sample_li's direction wi (the same from every point).
    float pdf_li(const LightSampleContext& /*ctx*/, const Vec3& wi) const {
        if (sampling == EnvironmentSampling::uniform) return 0.25f * kInvPi;
        return look_up(wi, &light_distribution()).pdf;
    }

    bool sample_li(const LightSampleContext& /*ctx*/, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        if (sampling == EnvironmentSampling::uniform) {
            ls.wi = sample_uniform_sphere(u1, u2);
            ls.pdf = 0.25f * kInvPi;
        } else {
            const PiecewiseConstant2D& dist = light_distribution();
            float square_pdf = 0.f;
            const auto [u, v] = dist.sample(u1, u2, &square_pdf);
            if (!(square_pdf > 0.f)) return false;
            ls.wi = normalize(to_world(map->direction_of(u, v)));
            // The density and radiance of the direction as a ray along it finds them (the
            // sampled square point and the direction's own may round into neighbouring texels).
            const Lookup at = look_up(ls.wi, &dist);
            ls.pdf = at.pdf;
            if (!(ls.pdf > 0.f) || !std::isfinite(ls.pdf)) return false;
            ls.L = radiance(at.texel, lambda);
            ls.infinite = true;
            return true;
        }
        ls.L = arriving(ls.wi, lambda);
        ls.infinite = true;
        return true;
    }

    /// Origin of a light subpath: a direction towards the map by its full density, then a
    /// point on the disk of radius R facing it, one radius upstream; the ray travels along
    /// o.w, away from the map.
    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float u3, float u4, float /*time*/) const {
        LightOrigin o;
        o.infinite = true;
        Vec3 towards;
        if (sampling == EnvironmentSampling::uniform) {
            towards = sample_uniform_sphere(u1, u2);
        } else {
            float square_pdf = 0.f;
            const auto [u, v] = map->distribution.sample(u1, u2, &square_pdf);
            if (!(square_pdf > 0.f)) return std::nullopt;
            towards = normalize(to_world(map->direction_of(u, v)));
        }
        o.w = -towards;
        o.pdf_dir = pdf_le_dir(Vec3(), o.w);
        if (!(o.pdf_dir > 0.f) || !std::isfinite(o.pdf_dir)) return std::nullopt;
        place_on_bounding_disk(o, center, radius, u3, u4);
        o.Le = arriving(towards, lambda);
        return o;
    }
    /// Solid-angle density of sample_le's direction w (the light arrives from −w).
    float pdf_le_dir(const Vec3& /*n*/, const Vec3& w) const {
        if (sampling == EnvironmentSampling::uniform) return 0.25f * kInvPi;
        return look_up(-w, &map->distribution).pdf;
    }
    /// Planar density of the disk point through which a ray travelling along d (unit)
    /// reaches p: 1/(πR²), or 0 when no ray leaving the disk passes through p.
    float pdf_le_pos(const Vec3& p, const Vec3& d) const {
        return bounding_disk_pdf_pos(center, radius, p, d);
    }

private:
    const PiecewiseConstant2D& light_distribution() const {
        return mis_compensation ? map->compensated : map->distribution;
    }
    /// What a direction (world, unit) finds in the map: the nearest texel and, given a
    /// distribution, its solid-angle density there. One mapping to the image serves both (its
    /// two arctangents are the costliest part of a look-up).
    struct Lookup {
        const RgbIlluminant& texel;
        float pdf = 0.f;
    };
    Lookup look_up(const Vec3& towards, const PiecewiseConstant2D* dist = nullptr) const {
        const Vec3 d = to_map(towards);
        const auto [u, v] = map->square_of(d);
        return {map->texel_at(u, v), dist ? map->solid_angle_pdf(dist->pdf(u, v), d) : 0.f};
    }
    SampledSpectrum radiance(const RgbIlluminant& t, const SampledWavelengths& lambda) const {
        return SampledSpectrum(scale * map->eval(t, lambda));
    }
};

/// The map of an image's texels: `values` holds `channels` floats per texel (1 or 2: grey,
/// 3 or 4: RGB; alpha is not read), row-major from the top row, linear radiance. Throws
/// std::invalid_argument, its message "what is wrong; expected what" (without the file's
/// name), for a texel that is not finite or negative, a map that emits nothing, and a
/// non-square equal-area map (of the first bad texel in row order). `compensated`: also build
/// the compensated distribution (for a light with mis_compensation). Rows are built on
/// `threads` threads (core/parallel_rows.h); the map is the same for every count. `values`
/// is released once read (pass it moved to keep the peak memory down).
std::shared_ptr<const EnvironmentMap> make_environment_map(int width, int height, int channels,
                                                           std::vector<float> values, EnvironmentMapping mapping,
                                                           bool compensated = false, int threads = load_threads());

}  // namespace spt
