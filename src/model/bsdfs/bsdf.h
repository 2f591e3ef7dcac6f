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
///                                for mode = importance the adjoint BSDF. A dispersive
///                                transmission evaluated while λ's companions live gives the
///                                hero's value × kLambdaCount and 0 for the companions: what
///                                a path that sampled it carries (dielectric.h), so every
///                                strategy estimates the same thing.
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
#include <type_traits>
#include <utility>
#include <variant>

#include "model/bsdfs/bsdf_sample.h"
#include "model/bsdfs/conductor.h"
#include "model/bsdfs/dielectric.h"
#include "model/bsdfs/diffuse.h"
#include "model/bsdfs/lobe_mix.h"
#include "model/bsdfs/plastic.h"
#include "model/bsdfs/thin_sheet.h"

namespace spt {

/// The types of the first wave come first: visit_bsdf tests indices in order, so the
/// common materials keep their short path.
using Bsdf = std::variant<DiffuseBsdf, LobeMixBsdf, ConductorBsdf, DielectricBsdf, PlasticBsdf, ThinSheetBsdf>;

/// Calls f with the BSDF's alternative: a chain of index tests, inlined, most common type
/// first (std::visit compiled to an out-of-line call through a table, and next-event
/// estimation to point lights spent 6 % more time per path with it).
template <std::size_t I = 0, typename F>
[[gnu::always_inline]] inline decltype(auto) visit_bsdf(const Bsdf& bsdf, F&& f) {
    if constexpr (I + 1 < std::variant_size_v<Bsdf>) {
        if (bsdf.index() != I) return visit_bsdf<I + 1>(bsdf, std::forward<F>(f));
    }
    return f(*std::get_if<I>(&bsdf));
}

inline BsdfFlags bsdf_flags(const Bsdf& bsdf) {
    return visit_bsdf(bsdf, [](const auto& b) { return b.flags(); });
}

inline SampledSpectrum bsdf_eval(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi,
                                                       const Vec3& n, const SampledWavelengths& lambda,
                                                       TransportMode mode) {
    return visit_bsdf(bsdf, [&](const auto& b) { return b.eval(wo, wi, n, lambda, mode); });
}

inline float bsdf_pdf(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, const Vec3& n,
                                            float hero_nm) {
    return visit_bsdf(bsdf, [&](const auto& b) { return b.pdf(wo, wi, n, hero_nm); });
}

/// Purely diffuse materials (most surfaces) are sampled inline; the others out of line.
[[gnu::always_inline]] inline std::optional<BsdfSample> bsdf_sample(const Bsdf& bsdf, const Vec3& wo,
                                                                   const Vec3& n, SampledWavelengths& lambda,
                                                                   float u_lobe, float u1, float u2,
                                                                   TransportMode mode) {
    if (dot(wo, n) == 0.f) return std::nullopt;  // exactly tangent: no side to scatter to
    // The diffuse case outside the visitor: an attribute on a lambda's operator() is not one
    // GCC 12 applies, and the lambda compiled to an out-of-line call from the path loop (13 %
    // of a diffuse scene's time was in it).
    if (const DiffuseBsdf* diffuse = std::get_if<DiffuseBsdf>(&bsdf)) [[likely]]
        return diffuse->sample(wo, n, lambda, u1, u2);
    return visit_bsdf(bsdf, [&](const auto& b) -> std::optional<BsdfSample> {
        if constexpr (std::is_same_v<std::decay_t<decltype(b)>, DiffuseBsdf>) __builtin_unreachable();  // above
        else return b.sample(wo, n, lambda, u_lobe, u1, u2, mode);
    });
}

}  // namespace spt
