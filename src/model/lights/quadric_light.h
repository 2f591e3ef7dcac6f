// An emitting disk, cylinder or cone: sampled by area (the shape's sample_area: a uniform
// point), for next-event estimation and emission alike; the area density is converted to
// solid angle at the reference point. The geometry is a copy of the scene's shape.
// A one-sided light (two_sided false) emits on the side of the shape's normal only (the
// disk's normal, the outside of a cylinder or cone): a sampled point that shows the reference
// point its back is no sample.
#pragma once
#include <optional>
#include <variant>

#include "geometry/cone.h"
#include "geometry/cylinder.h"
#include "geometry/disk.h"
#include "model/lights/area_emission.h"
#include "spectral/spectrum.h"

namespace spt {

struct QuadricLight {
    std::variant<Disk, Cylinder, Cone> shape;
    Spectrum Le;  ///< radiance
    bool two_sided = true;  ///< false: only the front (the side of the shape's normal) emits
    static constexpr LightType type = LightType::area;

    /// Radiance leaving the surface at p (normal n) along w.
    SampledSpectrum L(const Vec3& /*p*/, const Vec3& n, const Vec3& w, const SampledWavelengths& lambda) const {
        return emits_towards(two_sided, n, w) ? Le.sample(lambda) : SampledSpectrum(0.f);
    }

    float area() const {
        return std::visit([](const auto& s) { return s.area(); }, shape);
    }
    float power() const { return area_light_power(two_sided, area(), Le); }
    float spectral_power(float lambda_nm) const { return area_light_power(two_sided, area(), Le, lambda_nm); }

    SurfaceSample sample_point(float u1, float u2) const {
        return std::visit([&](const auto& s) { return s.sample_area(u1, u2); }, shape);
    }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const SurfaceSample ss = sample_point(u1, u2);
        ls.p = ss.p, ls.p_err = ss.p_err, ls.n = ss.n;
        if (!emits_towards(two_sided, ls.n, ctx.p - ls.p)) return false;
        ls.pdf = area_to_solid_angle(1.f / area(), ctx.p, ls.p, ls.n);
        return finish_area_sample(ls, ctx.p, Le.sample(lambda));
    }

    /// Density of the directions sample_li returns: 0 towards the back of a one-sided light.
    float pdf_li(const LightSampleContext& ctx, const Vec3& p_light, const Vec3& n_light) const {
        if (!emits_towards(two_sided, n_light, ctx.p - p_light)) return 0.f;
        return area_to_solid_angle(1.f / area(), ctx.p, p_light, n_light);
    }

    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float u_side,
                                         float u3, float u4, float /*time*/) const {
        const SurfaceSample ss = sample_point(u1, u2);
        LightOrigin o;
        o.p = ss.p, o.p_err = ss.p_err, o.n = ss.n;
        o.pdf_pos = 1.f / area();
        return emit_from_surface(o, Le.sample(lambda), two_sided, u_side, u3, u4);
    }
    float pdf_le_pos() const { return 1.f / area(); }
    float pdf_le_dir(const Vec3& n_light, const Vec3& w) const { return emission_direction_pdf(two_sided, n_light, w); }
};

}  // namespace spt
