// An emitting sphere. Next-event estimation samples the cone of directions it subtends
// (uniform in solid angle: every sampled direction hits it, unlike area sampling, whose
// far-side points are wasted and whose 1/cos peaks at the silhouette); from inside it samples
// the area. Emission (light subpaths) starts uniformly over the area. The geometry is a copy
// of the scene's sphere (the light answers without the scene).
#pragma once
#include <algorithm>
#include <optional>

#include "geometry/ray.h"
#include "geometry/sphere.h"
#include "model/lights/area_emission.h"
#include "spectral/spectrum.h"

namespace spt {

struct SphereLight {
    Sphere sphere;
    Spectrum Le;  ///< radiance, both sides
    int sphere_index = -1;  ///< the sphere's index in the scene (set by Scene::finalize)
    static constexpr LightType type = LightType::area;
    /// Both sides emit, always: a closed sphere is seen from outside only, so a one-sided one
    /// would differ only for points inside it.
    static constexpr bool two_sided = true;
    /// A closed surface: from outside, only its outside can be seen.
    static constexpr bool closed = true;

    /// Radiance leaving the surface at p (normal n) along w: the same from both sides.
    SampledSpectrum L(const Vec3& /*p*/, const Vec3& /*n*/, const Vec3& /*w*/, const SampledWavelengths& lambda) const {
        return Le.sample(lambda);
    }

    float area() const { return 4.f * kPi * sphere.radius * sphere.radius; }
    float power() const { return area_light_power(two_sided, area(), Le); }
    float spectral_power(float lambda_nm) const { return area_light_power(two_sided, area(), Le, lambda_nm); }

    /// Whether the reference point is inside (or on) the sphere, decided on the point pushed
    /// towards the centre past its error bound (pbrt-v4's Sphere::Sample): a point of the
    /// sphere's inner wall often rounds to just outside, and the cone from there would be a
    /// hemisphere whose nearest point is the shading point itself (4.6 % of inner-wall
    /// points: next-event estimation in a closed emitting sphere came out 1 % low).
    bool sees_from_inside(const LightSampleContext& ctx) const {
        // Clearly outside (beyond any rounding of p): no offset needed.
        const float r2 = sphere.radius * sphere.radius;
        if (length_squared(ctx.p - sphere.center) > r2 * 1.01f) return false;
        const Vec3 o = offset_ray_origin(ctx.p, ctx.p_err, ctx.n, sphere.center - ctx.p);
        return !(length_squared(o - sphere.center) > r2);
    }

    /// sin²θmax of the cone seen from ctx, or a negative value when ctx sees the inside.
    float sin2_theta_max(const LightSampleContext& ctx) const {
        if (sees_from_inside(ctx)) return -1.f;
        return sphere.radius * sphere.radius / length_squared(sphere.center - ctx.p);
    }

    /// 1 − cos θmax, with its small-angle limit sin²/2 where the difference would cancel.
    static float one_minus_cos(float sin2_max) {
        if (sin2_max < 1e-3f) return 0.5f * sin2_max + 0.125f * sin2_max * sin2_max;
        return 1.f - std::sqrt(1.f - sin2_max);
    }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const Vec3 from_center = ctx.p - sphere.center;
        const float dist2 = length_squared(from_center);
        const float r2 = sphere.radius * sphere.radius;
        if (sees_from_inside(ctx) || !(dist2 > r2)) {
            // Inside: a point uniform over the area, its density turned into solid angle.
            sample_point(u1, u2, ls.p, ls.p_err, ls.n);
            ls.pdf = area_to_solid_angle(1.f / area(), ctx.p, ls.p, ls.n);
        } else {
            // Outside: cos θ uniform in [cos θmax, 1] about the axis towards the centre, then the
            // point of the sphere that direction reaches first, found by the angle α at the
            // centre (pbrt-v4's Sphere::Sample, after Shirley): no ray-sphere test is needed.
            // Written with few square roots and divisions: they form one dependency chain.
            const float inv_dist = 1.f / std::sqrt(dist2);
            const float sin2_max = r2 / dist2;
            const float omc_max = one_minus_cos(sin2_max);
            const float omc = u1 * omc_max;        // 1 − cos θ
            const float sin2 = omc * (2.f - omc);  // sin²θ
            const float ratio = sin2 / sin2_max;   // sin²θ / sin²θmax, in [0, 1]
            // cos α = sin²θ/sin θmax + cos θ·√(1 − sin²θ/sin²θmax), with 1/sin θmax = d/r.
            const float cos_alpha = ratio * std::sqrt(sin2_max) + (1.f - omc) * safe_sqrt(1.f - ratio);
            const float sin_alpha = safe_sqrt(1.f - cos_alpha * cos_alpha);
            const float phi = 2.f * kPi * u2;
            const Frame f(from_center * inv_dist);  // axis from the centre to the viewer
            ls.n = f.to_world({sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha});
            ls.p = sphere.center + ls.n * sphere.radius;
            ls.p_err = point_error();
            ls.pdf = 1.f / (2.f * kPi * omc_max);
            // The point is the first the direction reaches: the sphere cannot hide it.
            ls.unoccluding_sphere = sphere_index;
        }
        return finish_area_sample(ls, ctx.p, Le.sample(lambda));
    }

    /// Density of sample_li producing the direction towards `p_light` (a point of the sphere
    /// found along it, normal n_light).
    float pdf_li(const LightSampleContext& ctx, const Vec3& p_light, const Vec3& n_light) const {
        const float sin2_max = sin2_theta_max(ctx);
        if (sin2_max < 0.f) return area_to_solid_angle(1.f / area(), ctx.p, p_light, n_light);
        return 1.f / (2.f * kPi * one_minus_cos(sin2_max));
    }

    /// Error bound of a point c + n·r of the sphere computed in float.
    Vec3 point_error() const {
        return (abs(sphere.center) + Vec3(sphere.radius, sphere.radius, sphere.radius)) * gamma_bound(6);
    }

    /// A point uniform over the surface.
    void sample_point(float u1, float u2, Vec3& p, Vec3& p_err, Vec3& n) const {
        n = sample_uniform_sphere(u1, u2);
        p = sphere.center + n * sphere.radius;
        p_err = point_error();
    }

    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float u_side,
                                         float u3, float u4, float /*time*/) const {
        LightOrigin o;
        sample_point(u1, u2, o.p, o.p_err, o.n);
        o.pdf_pos = 1.f / area();
        return emit_from_surface(o, Le.sample(lambda), two_sided, u_side, u3, u4);
    }
    float pdf_le_pos() const { return 1.f / area(); }
    float pdf_le_dir(const Vec3& n_light, const Vec3& w) const { return two_sided_direction_pdf(n_light, w); }

    /// The cap of the sphere that a ball (centre c, radius R) can see: the points whose
    /// outward normal has z ≥ z_min about the axis from the light's centre to the ball's
    /// (z_min = (r − R)/|c − c_L|: a point below it faces away from the whole ball; area
    /// 2πr²(1 − z_min)).
    struct VisibleCap {
        Vec3 axis;   ///< ball centre − light centre
        float dist;  ///< |axis|
        float z_min;
        float area_pdf(float r) const { return 1.f / (2.f * kPi * r * r * (1.f - z_min)); }
    };
    VisibleCap visible_cap(const Vec3& c, float R) const {
        const Vec3 axis = c - sphere.center;
        const float dist = length(axis);
        return {axis, dist, std::max(-1.f, (sphere.radius - R) / dist)};
    }

    /// A point y by area for a chain of specular bounces that ends on a ball (centre c,
    /// radius R): uniform over the cap the ball can see, density 1/(cap area).
    bool sample_area_facing(const Vec3& c, float R, float u1, float u2, Vec3& y, Vec3& ny, float& pdf_area) const {
        const VisibleCap cap = visible_cap(c, R);
        const float r = sphere.radius;
        const float z = 1.f - u1 * (1.f - cap.z_min);
        const float sz = std::sqrt(std::max(0.f, 1.f - z * z));
        const float phi = 2.f * kPi * u2;
        const Frame f(cap.axis / cap.dist);
        ny = f.to_world(Vec3(sz * std::cos(phi), sz * std::sin(phi), z));
        y = sphere.center + ny * r;
        pdf_area = cap.area_pdf(r);
        return true;
    }
    /// The density of sample_area_facing at a point y of the sphere (0 outside the cap).
    float pdf_area_facing(const Vec3& c, float R, const Vec3& y) const {
        const VisibleCap cap = visible_cap(c, R);
        const float r = sphere.radius;
        const float z = dot(y - sphere.center, cap.axis) / (cap.dist * r);
        if (z < cap.z_min) return 0.f;
        return cap.area_pdf(r);
    }
};

}  // namespace spt
