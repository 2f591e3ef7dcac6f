// An environment map sampled through a portal: a rectangle (a window, a door) that a scene
// names as the way its environment light comes in (Bitterli, Novák & Jarosz 2015,
// "Portal-masked environment map sampling"; pbrt-v4's PortalImageInfiniteLight). Sampling
// the whole sphere from inside a room wastes most samples on the walls; sampling the portal
// by area ignores the map. Here directions are drawn from the map's radiance restricted to
// exactly the directions that pass through the portal from the shading point.
//
// The portal's frame: x along edge1, y along edge2, z = x × y, the portal's front, facing the
// environment (outside). A direction w with w_z > 0 has rectified coordinates
//   u = (atan2(w_x, w_z) + π/2)/π,  v = (atan2(w_y, w_z) + π/2)/π,
// and from a point p behind the portal (p_z < 0) the directions through it form the
// axis-aligned rectangle of (u, v) between its corners' coordinates: each edge of the portal
// lies in a plane through p that keeps u (or v) fixed. The solid angle of a (u, v) cell is
// dω = π² (1 − w_x²)(1 − w_y²)/w_z du dv. A distribution over (u, v) weighs each cell by the
// map's importance density (luminance per solid angle) at its direction times that Jacobian,
// and is sampled within the rectangle (core/windowed_distribution.h); pdf_li divides by the
// Jacobian. The density is floored at 1e-3 of the uniform one, so that no direction through
// the portal has density 0 where the map's texels are finer than the cells, and a cell weighs
// at least a quarter of its brightest neighbour, so that the edge of a sun that a cell covers
// without any of its points seeing it does not get the sky's density (portal_light.cpp).
//
// A light sample is a one-sample mixture of the portal and the map's own density over the
// whole sphere (environment_map_light.h), both exact, so MIS sees their sum. The portal's
// share at a point follows P, the share of the whole-sphere density's samples that pass
// through the portal from there (the window's integral of the cells' weights; through_from
// below). Where the window shows only sky, P is small and the portal draws every sample;
// where a sun is seen through it, P is near 1 and the whole-sphere density, which draws the
// sun's texels exactly, takes over: the portal's cells do not line up with the texels, and
// at the sun's edges their density is several times off its radiance (docs/PERFORMANCE.md,
// "Portals").
//
// What the portal changes: only how light is sampled, never the radiance. An escaped ray
// sees the map in every direction, through the portal or not (pbrt-v4's Le is 0 unless the
// ray passed through the portal: the two agree for a room closed but for its portal).
// Directions that leave elsewhere (another opening) have only the whole-sphere share of the
// light density, 0 where the portal's share is 1; BSDF sampling finds them, with MIS weight
// 1 there: unbiased when BSDF sampling is combined, as in every integrator by default; with
// light sampling alone (`--light-sampling light`) they stay dark there, as they would in
// pbrt-v4. From a point not behind the portal the whole-sphere density alone samples the map.
//
// Light subpaths (bdpt, vcm) start on the portal itself: a point uniform over its area and
// a direction from the map over the whole (u, v) square, entering the room. pdf_pos is the
// density per unit area across the ray, 1/(A cos θ), θ between the ray and the portal's
// normal (the disk of an environment without a portal has 1/(πR²)); the flux through the
// portal is then E[Le/(pdf_pos·pdf_dir)] = A ∫ L cos θ dω, and power() is that integral
// (of the mean over 380–780 nm) by the midpoint rule over 256 × 256 cells of (u, v).
#pragma once
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include "core/fast_math.h"
#include "core/windowed_distribution.h"
#include "model/lights/environment_map_light.h"

namespace spt {

struct Portal {
    Vec3 origin, edge1, edge2;  ///< corners origin, + edge1, + edge1 + edge2, + edge2
    Vec3 x, y, z;               ///< unit edge1, unit edge2, x × y (towards the environment)
    float width = 0.f, height = 0.f;
};

/// What a portal light keeps (shared by its copies): the portal and its (u, v) distribution.
struct PortalSampling {
    Portal portal;
    WindowedPiecewiseConstant2D distribution;
    float power = 0.f;  ///< the flux through the portal (see above)
};

/// dω/d(u, v) = π² (1 − w_x²)(1 − w_y²)/w_z of a unit local direction, with 1 − w_x² as
/// w_y² + w_z²: near grazing (w_x → 1) the difference would round to 0.
inline float portal_jacobian(float wx, float wy, float wz) {
    return kPi * kPi * (wy * wy + wz * wz) * (wx * wx + wz * wz) / wz;
}

struct PortalLight {
    EnvironmentMapLight environment;  ///< the radiance (the map, its rotation and scale)
    std::shared_ptr<const PortalSampling> sampling;
    Vec3 center;  ///< the scene's bounding sphere (set as every infinite light's; unused here)
    float radius = 1.f;

    static constexpr LightType type = LightType::infinite;

    const Portal& portal() const { return sampling->portal; }

    float power() const { return sampling->power; }
    /// Flat: the map's spectrum varies over the directions through the portal (light.h).
    float spectral_power(float /*lambda_nm*/) const { return power(); }

    SampledSpectrum arriving(const Vec3& d, const SampledWavelengths& lambda) const {
        return environment.arriving(d, lambda);
    }

    /// (atan2(a, z) + π/2)/π for z > 0, in [0, 1]: the rectified coordinate of a direction (or
    /// an offset) with component a along an edge and z along the portal's normal. The sampled
    /// directions and their windows both come from here (and not std::atan2f, which cost a
    /// sample four library calls).
    static float rectified_coordinate(float a, float z) {
        return std::clamp(static_cast<float>(atan2_signed(a, z) / std::numbers::pi + 0.5), 0.f, 1.f);
    }
    /// The rectified coordinates of a world direction through the portal's front (false
    /// behind it), with dω/d(u, v).
    bool rectified(const Vec3& w, float& u, float& v, float& jacobian) const {
        const Portal& p = portal();
        const float wx = dot(w, p.x), wy = dot(w, p.y), wz = dot(w, p.z);
        if (!(wz > 0.f)) return false;
        u = rectified_coordinate(wx, wz);
        v = rectified_coordinate(wy, wz);
        jacobian = portal_jacobian(wx, wy, wz);
        return jacobian > 0.f;
    }
    Vec3 direction(float u, float v, float& jacobian) const {
        const Portal& p = portal();
        const float tx = std::tan((u - 0.5f) * kPi), ty = std::tan((v - 0.5f) * kPi);
        const float inv = 1.f / std::sqrt(1.f + tx * tx + ty * ty);
        const float wx = tx * inv, wy = ty * inv, wz = inv;
        jacobian = portal_jacobian(wx, wy, wz);
        return normalize(p.x * wx + p.y * wy + p.z * wz);
    }
    /// The (u, v) rectangle of the directions from q through the portal; false when q is not
    /// behind it.
    bool window(const Vec3& q, WindowedPiecewiseConstant2D::Window& w) const {
        const Portal& p = portal();
        const Vec3 r = q - p.origin;
        const float rx = dot(r, p.x), ry = dot(r, p.y), depth = -dot(r, p.z);
        if (!(depth > 0.f)) return false;
        w = {rectified_coordinate(-rx, depth), rectified_coordinate(-ry, depth), rectified_coordinate(p.width - rx, depth),
             rectified_coordinate(p.height - ry, depth)};
        return true;
    }

    /// What the light sampling of one shading point needs: its window through the portal, the
    /// window's integral of the cells' weights and the portal's share of the samples.
    struct Through {
        WindowedPiecewiseConstant2D::Window window;
        double integral = 0.0;
        float share = 0.f;  ///< 0: the whole sphere alone (also from points not behind the portal)
    };
    /// The portal's share follows P, the share of the whole-sphere density's samples that
    /// pass through the portal from q: the window's integral, as the cells' weights are that
    /// density per (u, v). Up to P = ½ the portal alone (the whole sphere would waste at least
    /// half its samples on the walls, and its density need not be evaluated), then 2(1 − P),
    /// down to 0 at P = 1: where a sun is seen through the window the whole-sphere density,
    /// which draws the sun's texels exactly and costs less, takes over. Near a sun the
    /// integral over-estimates P (cells are raised towards their brightest neighbour), which
    /// only hands the sun to the whole sphere sooner.
    Through through_from(const Vec3& q) const {
        Through t;
        if (!window(q, t.window)) return t;
        t.integral = sampling->distribution.integral(t.window);
        t.share = static_cast<float>(std::clamp(2.0 * (1.0 - t.integral), 0.0, 1.0));
        return t;
    }

    /// The one-sample mixture's density: share · portal + (1 − share) · whole sphere.
    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const { return pdf_li(ctx, through_from(ctx.p), wi); }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const Through t = through_from(ctx.p);
        if (u1 < t.share) {
            float u, v, square_pdf, jacobian;
            if (!sampling->distribution.sample(std::min(u1 / t.share, piecewise_detail::kOneMinusEpsilon), u2,
                                               t.window, u, v, square_pdf))
                return false;
            ls.wi = direction(u, v, jacobian);
            ls.L = arriving(ls.wi, lambda);
            ls.infinite = true;
        } else if (!environment.sample_li(
                       ctx, lambda, std::min((u1 - t.share) / (1.f - t.share), piecewise_detail::kOneMinusEpsilon), u2,
                       ls)) {
            return false;
        }
        // The density as a ray along the direction finds it (the rounding of the direction
        // may move it across a cell edge), of both strategies.
        ls.pdf = pdf_li(ctx, t, ls.wi);
        return ls.pdf > 0.f && std::isfinite(ls.pdf);
    }

    /// A light subpath's origin: a point on the portal, entering the room along o.w.
    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float /*u_side*/,
                                         float u3, float u4, float /*time*/) const {
        float u, v, square_pdf, jacobian;
        if (!sampling->distribution.sample(u1, u2, {}, u, v, square_pdf)) return std::nullopt;
        const Vec3 towards = direction(u, v, jacobian);
        LightOrigin o;
        o.infinite = true;
        o.w = -towards;
        o.pdf_dir = pdf_le_dir(Vec3(), o.w);
        const float cos_theta = dot(towards, portal().z);
        if (!(o.pdf_dir > 0.f) || !std::isfinite(o.pdf_dir) || !(cos_theta > 0.f)) return std::nullopt;
        o.p = portal().origin + portal().edge1 * u3 + portal().edge2 * u4;
        o.p_err = Vec3(0, 0, 0);
        o.Le = arriving(towards, lambda);
        o.pdf_pos = 1.f / (portal().width * portal().height * cos_theta);
        return o;
    }
    /// Solid-angle density of sample_le's direction w (the light arrives from −w).
    float pdf_le_dir(const Vec3& /*n*/, const Vec3& w) const {
        float u, v, jacobian;
        if (!rectified(-w, u, v, jacobian)) return 0.f;
        return sampling->distribution.pdf(u, v, {}) / jacobian;
    }
    /// Density across the ray of the portal point from which a ray travelling along d (unit)
    /// reaches p: 1/(A cos θ), or 0 when that ray does not come through the portal.
    float pdf_le_pos(const Vec3& p, const Vec3& d) const {
        const Portal& P = portal();
        const float cos_theta = -dot(d, P.z);
        if (!(cos_theta > 0.f)) return 0.f;
        const Vec3 r = p - P.origin;
        const float depth = -dot(r, P.z);
        if (!(depth >= 0.f)) return 0.f;
        const Vec3 q = r - d * (depth / cos_theta);  // the crossing of the portal's plane
        const float qx = dot(q, P.x), qy = dot(q, P.y);
        if (!(qx >= 0.f && qx <= P.width && qy >= 0.f && qy <= P.height)) return 0.f;
        return 1.f / (P.width * P.height * cos_theta);
    }

private:
    float pdf_li(const LightSampleContext& ctx, const Through& t, const Vec3& wi) const {
        float through = 0.f, u, v, jacobian;
        if (t.share > 0.f && t.integral > 0.0 && rectified(wi, u, v, jacobian))
            through = sampling->distribution.density(u, v, t.window, t.integral) / jacobian;
        return t.share * through + (t.share < 1.f ? (1.f - t.share) * environment.pdf_li(ctx, wi) : 0.f);
    }
};

/// The portal light of `environment` through the rectangle origin, + edge1, + edge2 (its
/// front, edge1 × edge2, facing the environment). Throws std::invalid_argument ("what is
/// wrong; expected what") for edges of zero length or not perpendicular.
PortalLight make_portal_light(const EnvironmentMapLight& environment, const Vec3& origin, const Vec3& edge1,
                              const Vec3& edge2);

}  // namespace spt
