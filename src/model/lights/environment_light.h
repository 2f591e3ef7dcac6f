// The constant environment: radiance Le arriving from every direction that escapes the
// scene. Next-event estimation samples a cosine-weighted direction about the shading normal
// on the side light is gathered from, or a uniform direction when the BSDF there transmits
// through a non-delta lobe (both sides matter).
//
// Light subpaths (pbrt's infinite lights): a direction d uniform over the sphere, then a
// point on the bounding sphere's disk facing d (bounding_disk.h). As a vertex the
// environment lies at infinity and is measured by direction: density 1/(4π) in solid angle
// (pdf_le_dir). See render/light_sampling.h for what the bounding sphere covers and why that
// stays unbiased.
#pragma once
#include <cmath>
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "model/lights/bounding_disk.h"
#include "model/lights/light_sample.h"
#include "spectral/spectrum.h"

namespace spt {

struct EnvironmentLight {
    Spectrum Le;
    Vec3 center;             ///< the scene's bounding sphere (light subpaths' disk)
    float radius = 1.f;

    static constexpr LightType type = LightType::infinite;

    float power() const { return 4.f * kPi * (kPi * radius * radius) * mean_over_visible(Le); }
    float spectral_power(float lambda_nm) const { return 4.f * kPi * (kPi * radius * radius) * Le.eval(lambda_nm); }

    /// Radiance arriving along a ray that escaped the scene (the same from every direction).
    SampledSpectrum arriving(const Vec3& /*d*/, const SampledWavelengths& lambda) const { return Le.sample(lambda); }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        if (ctx.both_sides) {
            ls.wi = sample_uniform_sphere(u1, u2);
            ls.pdf = 0.25f * kInvPi;
        } else {
            const Vec3 local = sample_cosine_hemisphere(u1, u2);
            if (!(local.z > 0.f)) return false;
            ls.wi = Frame(ctx.ns).to_world(local);
            ls.pdf = local.z * kInvPi;
        }
        ls.L = Le.sample(lambda);
        ls.infinite = true;
        return true;
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const {
        if (ctx.both_sides) return 0.25f * kInvPi;
        return cosine_hemisphere_pdf(dot(wi, ctx.ns));
    }

    /// Origin of a light subpath: the direction, then a point on the disk of radius R facing
    /// it, one radius upstream (pdf_pos: the disk's planar density; pdf_dir: per steradian).
    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float u3, float u4, float /*time*/) const {
        LightOrigin o;
        o.infinite = true;
        o.w = sample_uniform_sphere(u1, u2);
        place_on_bounding_disk(o, center, radius, u3, u4);
        o.Le = Le.sample(lambda);
        o.pdf_dir = pdf_le_dir(Vec3(), o.w);
        return o;
    }
    /// Solid-angle density of sample_le's direction.
    static float pdf_le_dir(const Vec3& /*n*/, const Vec3& /*w*/) { return 0.25f * kInvPi; }
    /// Planar density of the disk point through which a ray travelling along d (unit)
    /// reaches p: 1/(πR²), or 0 when no ray leaving the disk passes through p (p outside the
    /// cylinder the disk sweeps, or upstream of the disk).
    float pdf_le_pos(const Vec3& p, const Vec3& d) const {
        return bounding_disk_pdf_pos(center, radius, p, d);
    }
};

}  // namespace spt
