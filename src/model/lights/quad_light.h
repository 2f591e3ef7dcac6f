// An emitting rectangle (corner o, edges e1 and e2; Le from both sides, or one-sided from
// the front, the side of n = e1 × e2: see area_emission.h). Next-event
// estimation samples the solid angle it subtends, with the area-preserving parametrization
// of spherical rectangles (Ureña, Fajardo and King, EGSR 2013): every direction of the
// spherical rectangle is equally likely (pdf 1/Ω), so neither the 1/r² of a close light nor
// the 1/cos of a grazing view reaches the estimator (at 0.02 above a 0.5 × 0.5 light the
// irradiance variance is 1/260 of area sampling's).
//
// The parametrization needs orthogonal edges. A parallelogram whose edges are not
// orthogonal (|cos| > kMaxEdgeCos), and reference points from which the rectangle is a
// sliver (Ω < kMinSolidAngle) or nearly the whole hemisphere (Ω > 2π − kMaxSolidAngleGap:
// the point almost on the plane, where the inversion divides by vanishing sines), fall back
// to uniform area sampling converted to solid angle, like TriangleMeshLight. The choice
// depends on the reference point alone, so pdf_li makes the same one. A reference point on
// the plane (within its error bound and the rounding of the coordinates) sees the light
// edge-on: no sample, density 0. The angles and Ω are computed in double: Ω is a sum of
// four angles near π/2 minus 2π, which cancels in float long before Ω gets small.
//
// A one-sided light sends nothing to a reference point behind its plane: strategy() finds no
// sample there, so sample_li and pdf_li agree on it.
//
// Emission (light subpaths) starts uniformly over the area, on an emitting side.
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>

#include "geometry/ray.h"
#include "model/lights/area_emission.h"
#include "spectral/spectrum.h"

namespace spt {

struct QuadLight {
    Vec3 o, e1, e2;  ///< corner and edges (orthogonal for solid-angle sampling)
    Spectrum Le;     ///< radiance
    bool two_sided = true;  ///< false: only the front (the side of n) emits
    static constexpr LightType type = LightType::area;

    // Below: set by finish().
    Vec3 n;                 ///< unit normal, e1 × e2 normalised
    float total_area = 0.f;    ///< |e1 × e2|
    bool rectangular = false;  ///< edges orthogonal: the spherical-rectangle sampler applies
    double ux[3] = {}, uy[3] = {}, uz[3] = {};  ///< orthonormal frame: e1, e2 (orthogonalised), normal
    double len1 = 0, len2 = 0;                  ///< extents along ux and uy
    // Constant parts of strategy(), which runs for every light sample and MIS weight.
    Vec3 abs_n;                          ///< |n| per axis
    float corner_reach = 0.f;            ///< |n|·(|o| + |e1| + |e2|), for the on-the-plane tolerance
    double half_diagonal[3] = {};        ///< (e1 + e2)/2: the centre is o + half_diagonal

    /// Edges whose cosine exceeds this are a parallelogram: area sampling only.
    static constexpr double kMaxEdgeCos = 1e-5;
    /// Solid angles below this fall back to area sampling (a far or edge-on light: the two
    /// densities nearly agree there; Ω = Σ angles − 2π loses digits as 1e-16/Ω in double,
    /// it would be noise in float).
    static constexpr double kMinSolidAngle = 3e-4;
    /// Solid angles within this of 2π fall back to area sampling: the point is within about
    /// 1e-5 of the rectangle's size from its plane, where the inversion's 1 − cos² terms
    /// cancel (error ≈ 2e-16/gap in double) and the float coordinates of the sampled points
    /// start to resolve the distribution under the point coarsely (a few tens of ulps).
    static constexpr double kMaxSolidAngleGap = 1e-4;
    /// Below this estimated solid angle (sr) the rectangle is area-sampled: see strategy().
    static constexpr double kSolidAngleWorthIt = 0.1;

    /// Precomputes the normal, the area and the frame; call after setting o, e1, e2.
    void finish() {
        const double a[3] = {e1.x, e1.y, e1.z}, b[3] = {e2.x, e2.y, e2.z};
        const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        total_area = static_cast<float>(lc);
        for (int i = 0; i < 3; ++i) half_diagonal[i] = 0.5 * (a[i] + b[i]);
        if (!(lc > 0.0)) {  // degenerate: no light
            rectangular = false;
            n = Vec3(0, 0, 0);
            return;
        }
        for (int i = 0; i < 3; ++i) uz[i] = c[i] / lc, ux[i] = a[i] / la;
        // uy = uz × ux: e2 with its (tiny, within kMaxEdgeCos) component along e1 removed.
        uy[0] = uz[1] * ux[2] - uz[2] * ux[1];
        uy[1] = uz[2] * ux[0] - uz[0] * ux[2];
        uy[2] = uz[0] * ux[1] - uz[1] * ux[0];
        n = Vec3(static_cast<float>(uz[0]), static_cast<float>(uz[1]), static_cast<float>(uz[2]));
        abs_n = abs(n);
        corner_reach = dot(abs_n, abs(o) + abs(e1) + abs(e2));
        len1 = la;
        len2 = b[0] * uy[0] + b[1] * uy[1] + b[2] * uy[2];
        const double cos_edges = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
        rectangular = std::fabs(cos_edges) <= kMaxEdgeCos;
    }

    float area() const { return total_area; }
    /// Radiance leaving the surface at p (normal n) along w.
    SampledSpectrum L(const Vec3& /*p*/, const Vec3& n_hit, const Vec3& w, const SampledWavelengths& lambda) const {
        return emits_towards(two_sided, n_hit, w) ? Le.sample(lambda) : SampledSpectrum(0.f);
    }
    float power() const { return area_light_power(two_sided, total_area, Le); }
    float spectral_power(float lambda_nm) const { return area_light_power(two_sided, total_area, Le, lambda_nm); }

    /// The spherical rectangle seen from a reference point, in the frame (ux, uy, ±uz) centred
    /// there: the rectangle spans [x0, x1] × [y0, y1] in the plane z = z0 < 0 (the frame's z
    /// is turned away from the light), with the quantities the sampler inverts.
    struct SphericalRect {
        double x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0;
        double b0 = 0, b1 = 0;  ///< z components of the normals of the planes of the y0 and y1 edges
        double k = 0;           ///< 2π minus the two interior angles on the x0 side
        double solid_angle = 0;
    };
    enum class Strategy { none, area, solid_angle };

    /// How sample_li treats the reference point ctx (and pdf_li with it); fills r when the
    /// rectangle is sampled by solid angle. None behind a one-sided light.
    Strategy strategy(const LightSampleContext& ctx, SphericalRect& r) const {
        if (!(total_area > 0.f)) return Strategy::none;
        const double d[3] = {double(o.x) - ctx.p.x, double(o.y) - ctx.p.y, double(o.z) - ctx.p.z};
        const double z0 = d[0] * uz[0] + d[1] * uz[1] + d[2] * uz[2];
        // On the plane: within the point's error bound, or closer than the float rounding of
        // p_light − p along n (below that, area_to_solid_angle's cosine is noise).
        const double tol = dot(abs_n, ctx.p_err) + double(gamma_bound(4)) * (dot(abs_n, abs(ctx.p)) + corner_reach);
        // In front of the plane (the side of n) z0 < 0; a one-sided light needs that.
        const double reach = two_sided ? std::fabs(z0) : -z0;
        if (!(reach > tol)) return Strategy::none;
        if (!rectangular) return Strategy::area;
        // Far from the light, area sampling is almost as good and much cheaper (the map needs
        // four arc tangents): solid angle only where the rectangle looks large, by the
        // estimate Ω ≈ A·|z0|/d³ from its centre. Past 0.1 sr the solid-angle map's lower
        // noise pays for its cost; below, area sampling gives nearly the same error for far
        // less time (docs/PERFORMANCE.md, "Light samplers").
        const double cx = d[0] + half_diagonal[0], cy = d[1] + half_diagonal[1], cz = d[2] + half_diagonal[2];
        const double dc2 = cx * cx + cy * cy + cz * cz;
        if (double(total_area) * std::fabs(z0) < kSolidAngleWorthIt * dc2 * std::sqrt(dc2)) return Strategy::area;
        r.z0 = -std::fabs(z0);  // turning z away from the light mirrors the frame: Ω and the map are unchanged
        r.x0 = d[0] * ux[0] + d[1] * ux[1] + d[2] * ux[2];
        r.y0 = d[0] * uy[0] + d[1] * uy[1] + d[2] * uy[2];
        r.x1 = r.x0 + len1;
        r.y1 = r.y0 + len2;
        const double z = r.z0, az = -z;
        // Interior angle at each corner v = (x, y, z0) between its two edges' planes through
        // the reference point: from the planes' normals, cos = ±x·y / (|n_a||n_b|) and
        // sin = |z0|·|v| / (|n_a||n_b|); atan2 keeps the angles near 0 and π accurate.
        auto len = [z](double x, double y) { return std::sqrt(x * x + y * y + z * z); };
        const double g0 = std::atan2(az * len(r.x1, r.y0), r.x1 * r.y0);   // at (x1, y0)
        const double g1 = std::atan2(az * len(r.x1, r.y1), -r.x1 * r.y1);  // at (x1, y1)
        const double g2 = std::atan2(az * len(r.x0, r.y1), r.x0 * r.y1);   // at (x0, y1)
        const double g3 = std::atan2(az * len(r.x0, r.y0), -r.x0 * r.y0);  // at (x0, y0)
        constexpr double k2Pi = 2.0 * 3.14159265358979323846;
        r.solid_angle = g0 + g1 + g2 + g3 - k2Pi;
        if (!(r.solid_angle >= kMinSolidAngle) || !(r.solid_angle <= k2Pi - kMaxSolidAngleGap)) return Strategy::area;
        r.k = k2Pi - g2 - g3;
        r.b0 = -r.y0 / std::sqrt(z * z + r.y0 * r.y0);  // plane of the y0 edge: normal ∝ (0, z0, −y0)
        r.b1 = r.y1 / std::sqrt(z * z + r.y1 * r.y1);   // plane of the y1 edge: normal ∝ (0, −z0, y1)
        return Strategy::solid_angle;
    }

    /// The point of the rectangle for (u1, u2) under the area-preserving map: u1 fixes the
    /// plane x = xu holding the share u1 of Ω on its x0 side, u2 the height along that
    /// plane's arc, uniform in the sine of the elevation (h). Returns the rectangle's (s, t).
    static void warp(const SphericalRect& r, double u1, double u2, double len1, double len2, double& s, double& t) {
        // The sub-rectangle [x0, xu] has interior angles sum au = u1·Ω + k on its xu side; the
        // cosine of the angle of the plane x = xu with the y axis follows in closed form.
        const double au = u1 * r.solid_angle + r.k;
        const double fu = (std::cos(au) * r.b0 - r.b1) / std::sin(au);
        const double cu = std::clamp(std::copysign(1.0, fu) / std::sqrt(fu * fu + r.b0 * r.b0), -1.0, 1.0);
        const double sin_u = std::sqrt(std::max(0.0, (1.0 - cu) * (1.0 + cu)));
        double xu = sin_u > 0.0 ? -cu * r.z0 / sin_u : (cu > 0.0 ? r.x1 : r.x0);
        if (!(xu >= r.x0)) xu = r.x0;  // also catches NaN
        if (!(xu <= r.x1)) xu = r.x1;
        // Along the chosen line the elevation's sine h is uniform between its ends.
        const double dist2 = xu * xu + r.z0 * r.z0, dist = std::sqrt(dist2);
        const double h0 = r.y0 / std::sqrt(dist2 + r.y0 * r.y0);
        const double h1 = r.y1 / std::sqrt(dist2 + r.y1 * r.y1);
        const double hv = h0 + u2 * (h1 - h0);
        const double cos2 = (1.0 - hv) * (1.0 + hv);
        double yv = cos2 > 0.0 ? hv * dist / std::sqrt(cos2) : (hv > 0.0 ? r.y1 : r.y0);
        if (!(yv >= r.y0)) yv = r.y0;
        if (!(yv <= r.y1)) yv = r.y1;
        s = std::clamp((xu - r.x0) / len1, 0.0, 1.0);
        t = std::clamp((yv - r.y0) / len2, 0.0, 1.0);
    }

    /// The point o + s·e1 + t·e2 (computed in double), its error bound and the normal.
    void point_at(double s, double t, Vec3& p, Vec3& p_err) const {
        p = Vec3(static_cast<float>(o.x + s * e1.x + t * e2.x), static_cast<float>(o.y + s * e1.y + t * e2.y),
                 static_cast<float>(o.z + s * e1.z + t * e2.z));
        p_err = (abs(o) + abs(e1) + abs(e2)) * gamma_bound(7) + rounded_point_error(p);
    }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        SphericalRect r;
        const Strategy how = strategy(ctx, r);
        if (how == Strategy::none) return false;
        ls.n = n;
        ls.planar = true;  // `none` above: the reference point is off the plane
        if (how == Strategy::solid_angle) {
            double s, t;
            warp(r, u1, u2, len1, len2, s, t);
            point_at(s, t, ls.p, ls.p_err);
            ls.pdf = static_cast<float>(1.0 / r.solid_angle);
        } else {
            point_at(u1, u2, ls.p, ls.p_err);
            ls.pdf = area_to_solid_angle(1.f / total_area, ctx.p, ls.p, n);
        }
        return finish_area_sample(ls, ctx.p, Le.sample(lambda));
    }

    /// Density of sample_li producing the direction towards p_light (a point of the rectangle;
    /// the rectangle's own normal is used, n_light only names the interface's argument).
    float pdf_li(const LightSampleContext& ctx, const Vec3& p_light, const Vec3& /*n_light*/) const {
        SphericalRect r;
        switch (strategy(ctx, r)) {
        case Strategy::none: return 0.f;
        case Strategy::solid_angle: return static_cast<float>(1.0 / r.solid_angle);
        case Strategy::area: break;
        }
        return area_to_solid_angle(1.f / total_area, ctx.p, p_light, n);
    }

    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float u_side,
                                         float u3, float u4, float /*time*/) const {
        if (!(total_area > 0.f)) return std::nullopt;
        LightOrigin lo;
        point_at(u1, u2, lo.p, lo.p_err);
        lo.n = n;
        lo.pdf_pos = 1.f / total_area;
        return emit_from_surface(lo, Le.sample(lambda), two_sided, u_side, u3, u4);
    }
    float pdf_le_pos() const { return 1.f / total_area; }
    float pdf_le_dir(const Vec3& n_light, const Vec3& w) const { return emission_direction_pdf(two_sided, n_light, w); }

    /// A point y of the surface by area for a chain of specular bounces that ends on a ball
    /// (centre c, radius R; the rectangle ignores it): uniform, density 1/area.
    bool sample_area_facing(const Vec3& /*c*/, float /*R*/, float u1, float u2, Vec3& y, Vec3& ny,
                            float& pdf_area) const {
        y = o + e1 * u1 + e2 * u2;
        ny = n;
        pdf_area = 1.f / area();
        return true;
    }
    float pdf_area_facing(const Vec3& /*c*/, float /*R*/, const Vec3& /*y*/) const { return 1.f / area(); }
};

}  // namespace spt
