// An emitting disk, cylinder or cone: sampled by area (the shape's sample_area: a uniform
// point), for next-event estimation and emission alike; the area density is converted to
// solid angle at the reference point. The geometry is a copy of the scene's shape.
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
    Spectrum Le;  ///< radiance, both sides
    static constexpr LightType type = LightType::area;
    static constexpr bool two_sided = true;

    /// Radiance leaving the surface at p (normal n) along w: the same from both sides.
    SampledSpectrum L(const Vec3& /*p*/, const Vec3& /*n*/, const Vec3& /*w*/, const SampledWavelengths& lambda) const {
        return Le.sample(lambda);
    }

    float area() const {
        return std::visit([](const auto& s) { return s.area(); }, shape);
    }
    float power() const { return 2.f * kPi * area() * mean_over_visible(Le); }

    SurfaceSample sample_point(float u1, float u2) const {
        return std::visit([&](const auto& s) { return s.sample_area(u1, u2); }, shape);
    }

    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const SurfaceSample ss = sample_point(u1, u2);
        ls.p = ss.p, ls.p_err = ss.p_err, ls.n = ss.n;
        ls.pdf = area_to_solid_angle(1.f / area(), ctx.p, ls.p, ls.n);
        return finish_area_sample(ls, ctx.p, Le.sample(lambda));
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& p_light, const Vec3& n_light) const {
        return area_to_solid_angle(1.f / area(), ctx.p, p_light, n_light);
    }

    std::optional<LightOrigin> sample_le(const SampledWavelengths& lambda, float u1, float u2, float u_side,
                                         float u3, float u4, float /*time*/) const {
        const SurfaceSample ss = sample_point(u1, u2);
        LightOrigin o;
        o.p = ss.p, o.p_err = ss.p_err, o.n = ss.n;
        o.pdf_pos = 1.f / area();
        return emit_two_sided(o, Le.sample(lambda), u_side, u3, u4);
    }
    float pdf_le_pos() const { return 1.f / area(); }
    float pdf_le_dir(const Vec3& n_light, const Vec3& w) const { return two_sided_direction_pdf(n_light, w); }
};

}  // namespace spt
