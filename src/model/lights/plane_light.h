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

    /// Signed distance of p from the plane along its normal (double: p may lie far away).
    double side(const Vec3& p) const {
        return double(plane.normal.x) * p.x + double(plane.normal.y) * p.y + double(plane.normal.z) * p.z -
               plane.offset;
    }
    /// Unit normal of the plane turned towards it from p; zero when p lies on the plane.
    Vec3 towards(const Vec3& p) const {
        const double s = side(p);
        if (s == 0.0) return {};
        return s > 0.0 ? -plane.normal : plane.normal;
    }

    std::optional<LightSample> sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1,
                                         float u2) const {
        const double s = side(ctx.p);
        if (s == 0.0) return std::nullopt;
        const Vec3 axis = s > 0.0 ? -plane.normal : plane.normal;
        const Vec3 local = sample_cosine_hemisphere(u1, u2);
        if (!(local.z > 0.f)) return std::nullopt;
        LightSample ls;
        ls.wi = Frame(axis).to_world(local);
        // The distance along wi: |side| / cos θ (the shadow ray needs no point on the plane).
        ls.plane_distance = static_cast<float>(std::fabs(s) / local.z);
        if (!std::isfinite(ls.plane_distance)) return std::nullopt;
        ls.pdf = local.z * kInvPi;
        ls.L = Le.sample(lambda);
        return ls;
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const {
        return cosine_hemisphere_pdf(dot(wi, towards(ctx.p)));
    }
};

}  // namespace spt
