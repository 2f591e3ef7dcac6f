// An emitting set of triangles: one triangle, the two of a quad, or a whole mesh, as one
// light. Sampled by area (a triangle by its area, then a uniform point: the square-root warp
// of the barycentrics), for next-event estimation and emission alike; the area density is
// converted to solid angle at the reference point. (Spherical-triangle sampling would remove
// the 1/cos of grazing views; area sampling is what this light states and tests.)
// A one-sided light (two_sided false) emits from each triangle's front only (normal
// (p1 − p0) × (p2 − p0)): a sampled point that shows the reference point its back is no sample.
#pragma once
#include <algorithm>
#include <optional>
#include <vector>

#include "geometry/triangle.h"
#include "model/lights/area_emission.h"
#include "spectral/spectrum.h"

namespace spt {

struct TriangleMeshLight {
    std::vector<Triangle> triangles;  ///< copies of the scene's triangles of this shape
    std::vector<float> cdf;           ///< cumulative area fractions (last = 1)
    float total_area = 0.f;
    Spectrum Le;  ///< radiance
    bool two_sided = true;  ///< false: only the front (the side of the shape's normal) emits
    static constexpr LightType type = LightType::area;

    /// Radiance leaving the surface at p (normal n) along w.
    SampledSpectrum L(const Vec3& /*p*/, const Vec3& n, const Vec3& w, const SampledWavelengths& lambda) const {
        return emits_towards(two_sided, n, w) ? Le.sample(lambda) : SampledSpectrum(0.f);
    }

    static float triangle_area(const Triangle& t) { return 0.5f * length(cross(t.p1 - t.p0, t.p2 - t.p0)); }

    /// Adds a triangle (before finish()).
    void add(const Triangle& t) { triangles.push_back(t); }
    /// Builds the area distribution.
    void finish() {
        double sum = 0;
        cdf.clear();
        for (const Triangle& t : triangles) cdf.push_back(static_cast<float>(sum += triangle_area(t)));
        total_area = static_cast<float>(sum);
        for (float& c : cdf) c = static_cast<float>(c / sum);
        if (!cdf.empty()) cdf.back() = 1.f;
    }

    float power() const { return area_light_power(two_sided, total_area, Le); }
    float spectral_power(float lambda_nm) const { return area_light_power(two_sided, total_area, Le, lambda_nm); }

    /// A point uniform over the whole area (u1 picks the triangle and is reused inside it);
    /// `triangle` is the index of the one it is on.
    void sample_point(float u1, float u2, Vec3& p, Vec3& p_err, Vec3& n, std::uint32_t& triangle) const {
        const auto it = std::upper_bound(cdf.begin(), cdf.end(), u1);
        const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - cdf.begin()), cdf.size() - 1);
        const float lo = k > 0 ? cdf[k - 1] : 0.f;
        const float u = std::clamp((u1 - lo) / std::max(cdf[k] - lo, 1e-30f), 0.f, 0x1.fffffep-1f);
        point_on(k, u, u2, p, p_err, n);
        triangle = static_cast<std::uint32_t>(k);
    }
    /// A point uniform on triangle k (u in [0, 1) the square-root warp's number).
    void point_on(std::size_t k, float u, float u2, Vec3& p, Vec3& p_err, Vec3& n) const {
        const Triangle& t = triangles[k];
        const float su = std::sqrt(u);
        const float b0 = 1.f - su, b1 = u2 * su, b2 = 1.f - b0 - b1;
        p = t.p0 * b0 + t.p1 * b1 + t.p2 * b2;
        p_err = (abs(t.p0 * b0) + abs(t.p1 * b1) + abs(t.p2 * b2)) * gamma_bound(7) + rounded_point_error(p);
        n = normalize(cross(t.p1 - t.p0, t.p2 - t.p0));
    }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        sample_point(u1, u2, ls.p, ls.p_err, ls.n, ls.triangle);
        if (!emits_towards(two_sided, ls.n, ctx.p - ls.p)) return false;
        ls.pdf = area_to_solid_angle(1.f / total_area, ctx.p, ls.p, ls.n);
        return finish_area_sample(ls, ctx.p, Le.sample(lambda));
    }

    /// sample_li with the point on triangle k (a light BVH chose it, render/light_bvh.h): the
    /// density stated is sample_li's own (1 / total_area in solid angle); the chooser's
    /// probability carries the ratio of the areas.
    bool sample_li_on(std::uint32_t k, const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1,
                      float u2, LightSample& ls) const {
        point_on(k, std::min(u1, 0x1.fffffep-1f), u2, ls.p, ls.p_err, ls.n);
        ls.triangle = k;
        if (!emits_towards(two_sided, ls.n, ctx.p - ls.p)) return false;
        ls.pdf = area_to_solid_angle(1.f / total_area, ctx.p, ls.p, ls.n);
        return finish_area_sample(ls, ctx.p, Le.sample(lambda));
    }

    /// Density of the directions sample_li returns: 0 towards the back of a one-sided light.
    float pdf_li(const LightSampleContext& ctx, const Vec3& p_light, const Vec3& n_light) const {
        if (!emits_towards(two_sided, n_light, ctx.p - p_light)) return 0.f;
        return area_to_solid_angle(1.f / total_area, ctx.p, p_light, n_light);
    }

    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float u_side,
                                         float u3, float u4, float /*time*/) const {
        LightOrigin o;
        sample_point(u1, u2, o.p, o.p_err, o.n, o.triangle);
        o.pdf_pos = 1.f / total_area;
        return emit_from_surface(o, Le.sample(lambda), two_sided, u_side, u3, u4);
    }
    float pdf_le_pos() const { return 1.f / total_area; }
    float pdf_le_dir(const Vec3& n_light, const Vec3& w) const { return emission_direction_pdf(two_sided, n_light, w); }
};

}  // namespace spt
