// The closed set of BSDFs and the one contract every type in it fulfils. Adding a type is
// one header in this folder and one entry in `Bsdf`; integrators only ask these questions
// (and the flags), never which type or fields a material has.
//
// Conventions: directions point away from the surface and are unit; n is the shading normal
// (either side: each type decides by the signs of dot(wo, n) and dot(wi, n)); λ is the
// path's wavelength set, the hero first.
//
///  flags()                       what the BSDF can do (BsdfFlags): reflection, transmission,
///                                a non-delta lobe (light sampling, connections, merging),
///                                a delta lobe, wavelength-dependent directions.
///  eval(wo, wi, n, λ, mode)      f(wo, wi)·|cos θi| of the non-delta lobes, per wavelength;
///                                for mode = importance the adjoint BSDF.
///  pdf(wo, wi, n, hero)          solid-angle density with which sample() produces wi from
///                                wo through its non-delta lobes, the lobe choice made at the
///                                hero wavelength (the density MIS weights use: the same
///                                function for every strategy); 0 where eval is 0.
///  sample(wo, n, λ, u, u1, u2, mode)
///                                a lobe, then a direction: {wi, weight = f·|cos θi|/density,
///                                pdf (as pdf(), 0 for a delta lobe), flags of the lobe,
///                                eta_scale}; nullopt when no direction results (a degenerate
///                                or absorbed sample). A dispersive refraction terminates λ's
///                                companions. A black BSDF (flags().is_black(): no lobe) is
///                                never sampled; integrators end paths there.
#pragma once
#include <optional>
#include <variant>

#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/diffuse.h"
#include "model/bsdfs/lobe_mix.h"

namespace spt {

using Bsdf = std::variant<DiffuseBsdf, LobeMixBsdf>;

inline BsdfFlags bsdf_flags(const Bsdf& bsdf) {
    return std::visit([](const auto& b) { return b.flags(); }, bsdf);
}

// Each dispatch tests for the diffuse type first, inline: it is most surfaces, and as an
// out-of-line std::visit the evaluation cost 9 % of the time per path in next-event
// estimation on cornell.
[[gnu::always_inline]] inline SampledSpectrum bsdf_eval(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi,
                                                       const Vec3& n, const SampledWavelengths& lambda,
                                                       TransportMode mode) {
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&bsdf)) return d->eval(wo, wi, n, lambda, mode);
    return std::visit([&](const auto& b) { return b.eval(wo, wi, n, lambda, mode); }, bsdf);
}

[[gnu::always_inline]] inline float bsdf_pdf(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, const Vec3& n,
                                            float hero_nm) {
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&bsdf)) return d->pdf(wo, wi, n, hero_nm);
    return std::visit([&](const auto& b) { return b.pdf(wo, wi, n, hero_nm); }, bsdf);
}

/// Purely diffuse materials (most surfaces) are sampled inline; the others out of line.
[[gnu::always_inline]] inline std::optional<BsdfSample> bsdf_sample(const Bsdf& bsdf, const Vec3& wo,
                                                                   const Vec3& n, SampledWavelengths& lambda,
                                                                   float u_lobe, float u1, float u2,
                                                                   TransportMode mode) {
    if (dot(wo, n) == 0.f) return std::nullopt;  // exactly tangent: no side to scatter to
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&bsdf)) return d->sample(wo, n, lambda, u1, u2);
    return std::get<LobeMixBsdf>(bsdf).sample(wo, n, lambda, u_lobe, u1, u2, mode);
}

}  // namespace spt
