// The constant environment: radiance Le arriving from every direction that escapes the
// scene. Next-event estimation samples a cosine-weighted direction about the shading normal
// on the side light is gathered from, or a uniform direction when the BSDF there transmits
// through a non-delta lobe (both sides matter). Light subpaths start on a disk facing the
// scene's bounding sphere (bidirectional integrators; see render/light_sampling.h).
#pragma once
#include <optional>

#include "core/frame.h"
#include "core/sampling.h"
#include "model/lights/light_sample.h"
#include "spectral/spectrum.h"

namespace spt {

struct EnvironmentLight {
    Spectrum Le;
    Vec3 center;             ///< the scene's bounding sphere (light subpaths' disk)
    float radius = 1.f;

    float power() const { return 4.f * kPi * (kPi * radius * radius) * mean_over_visible(Le); }

    std::optional<LightSample> sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1,
                                         float u2) const {
        LightSample ls;
        if (ctx.both_sides) {
            ls.wi = sample_uniform_sphere(u1, u2);
            ls.pdf = 0.25f * kInvPi;
        } else {
            const Vec3 local = sample_cosine_hemisphere(u1, u2);
            if (!(local.z > 0.f)) return std::nullopt;
            ls.wi = Frame(ctx.ns).to_world(local);
            ls.pdf = local.z * kInvPi;
        }
        ls.L = Le.sample(lambda);
        ls.infinite = true;
        return ls;
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const {
        if (ctx.both_sides) return 0.25f * kInvPi;
        return cosine_hemisphere_pdf(dot(wi, ctx.ns));
    }
};

}  // namespace spt
