// An emitting infinite plane (the Cornell ceiling): Le from both sides. It has no finite
// area, so next-event estimation samples a direction: cosine-weighted about the plane's
// normal turned towards it from the reference point. Every such direction reaches the plane
// (the half-space of directions that sees it), and the density falls to 0 towards its
// horizon, where the plane recedes. It cannot start light subpaths (no area to sample).
#pragma once
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "geometry/plane.h"
#include "model/lights/light_sample.h"
#include "spectral/spectrum.h"

namespace spt {

struct PlaneLight {
    Plane plane;
    Spectrum Le;  ///< radiance, both sides
    /// The radius of the scene's bounding sphere: the plane's power for light selection is
    /// what it sends into a disk of that radius, π·Le·πR² (it has no finite power).
    float scene_radius = 1.f;

    float power() const { return kPi * kPi * scene_radius * scene_radius * mean_over_visible(Le); }

    /// Unit normal of the plane turned towards it from p; zero when p lies on the plane.
    Vec3 towards(const Vec3& p) const {
        const double side = double(plane.normal.x) * p.x + double(plane.normal.y) * p.y +
                            double(plane.normal.z) * p.z - plane.offset;
        if (side == 0.0) return {};
        return side > 0.0 ? -plane.normal : plane.normal;
    }

    std::optional<LightSample> sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1,
                                         float u2) const {
        const Vec3 axis = towards(ctx.p);
        if (axis == Vec3{}) return std::nullopt;
        const Vec3 local = sample_cosine_hemisphere(u1, u2);
        if (!(local.z > 0.f)) return std::nullopt;
        LightSample ls;
        ls.wi = Frame(axis).to_world(local);
        const double t = plane.intersect_t({ctx.p, ls.wi, kInfinity});
        if (!(t < kInfinity)) return std::nullopt;  // rounding at the horizon
        const Hit h = plane.make_hit({ctx.p, ls.wi, kInfinity}, t);
        if (!is_finite(h.p)) return std::nullopt;
        ls.p = h.p;
        ls.p_err = h.p_err;
        ls.n = plane.normal;
        ls.pdf = local.z * kInvPi;
        ls.L = Le.sample(lambda);
        return ls;
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const {
        return cosine_hemisphere_pdf(dot(wi, towards(ctx.p)));
    }
};

}  // namespace spt
