// Specular next-event estimation through smooth glass spheres: caustics (light → glass ball
// → diffuse surface → eye) sampled from the diffuse vertex instead of waiting for BSDF
// sampling to hit a small light through the ball (fireflies). Exact, without clamping:
//
//   At a vertex x with a non-delta lobe, the refraction chain is chosen with probability
//   SphereChains::refraction_share (else the reflection chain of render/reflection_nee.h),
//   one glass sphere of SphereChains::caustic_spheres uniformly (together P_s = share/N)
//   and one light of SphereChains::light_choice by power (P_l); a point y on it is sampled
//   by area: uniformly over a quad (p_A = 1/area), or over the cap of an emitting sphere
//   that any point of the glass ball can see (z = cos of the angle at the light's centre
//   from the direction to the ball's centre, z ≥ (r − R)/|c − c_L|: a
//   point of the light below that cap faces away from the whole ball; p_A = 1/cap area). The
//   chain x → refract in → refract out → y is then solved for all its roots
//   (geometry/sphere_caustics.h), and each root contributes
//     f(x, ω)·|cos| · kt²·T_in·T_out · Le(y) · |dω_x/dA_y| / (P_s·P_l·p_A(y)) · w_snee
//   when the three segments (x → entry, the chord, exit → y) are clear (each tested over its
//   interior, shortened by 1e-4 of its length at each end: the glass sphere and the light
//   they end on cannot block them). T = 1 − F is the renderer's Fresnel (fresnel_dielectric,
//   the function both glass BSDFs sample their lobe by). The radiance scaling of the two
//   refractions cancels (1/η² in, η² out).
//
//   MIS (power heuristic, Veach 1997 §9.2) against BSDF sampling of the same path, whose
//   density is p_bsdf(ω_x)·(1 − F_in)·(1 − F_out) (the glass samples transmission with
//   probability 1 − F at the hero, which for a constant index is every wavelength's), while
//   this strategy's is p_snee = P_s·P_l·p_A(y)/|dω_x/dA_y|. The path loop, when its BSDF
//   sampling goes x (non-delta) → refract into a caustic sphere → refract out of it → an
//   emitter, weights that emission by p_chain²/(p_chain² + p_snee²) — but only if this solver,
//   given the same x and y, returns the path's root (emission_weight below asks it): a root
//   the grid misses near a fold keeps weight 1 on the BSDF side, so the sum stays exact.
//   Paths that this strategy cannot produce keep the light sampler's weights: emission after other
//   delta chains (weight 1), lights it does not sample (mesh, disk and plane lights, the
//   infinite lights, textured emitters, point lights), dispersive or rough glass, reflections off
//   the sphere (D-R-L) and internal reflections (TRT...). Media scenes: not used.
//
//   It runs only with --light-sampling mis (the default) and only where the BSDF sampling of
//   the path could reach the same path before --max-depth: x at depth d with d + 2 <
//   max_depth (the two refractions are bounces d + 1 and d + 2).
#pragma once
#include <cmath>

#include "geometry/sphere_caustics.h"
#include "model/bsdfs/bsdf.h"
#include "model/bsdfs/fresnel.h"
#include "render/integrator.h"
#include "render/mis.h"
#include "scene/scene.h"

namespace spt {

/// The density per unit area with which the strategy samples y on light `index` for sphere
/// `sphere` (index in Scene::spheres; 0 when the light is not one it samples by area, or y is
/// outside the part of it the ball can see): the light's pdf_area_facing.
inline float caustic_light_area_pdf(const Scene& scene, int sphere, int index, const Vec3& y) {
    const Sphere& ball = scene.spheres[static_cast<std::size_t>(sphere)];
    return light_pdf_area_facing(scene.lights[static_cast<std::size_t>(index)], ball.center, ball.radius, y);
}

/// A point y on light `index` sampled by area for sphere `sphere` (index in Scene::spheres),
/// with its normal and density (the light's sample_area_facing); false when the light is not
/// one the strategy samples.
inline bool caustic_light_sample(const Scene& scene, int sphere, int index, float u1, float u2, Vec3& y,
                                 Vec3& n, float& pdf_area) {
    const Sphere& ball = scene.spheres[static_cast<std::size_t>(sphere)];
    return light_sample_area_facing(scene.lights[static_cast<std::size_t>(index)], ball.center, ball.radius, u1, u2,
                                    y, n, pdf_area);
}

/// The shadow test of the segment a → b over its interior (1e-4 of its length off each end).
inline bool caustic_segment_blocked(const Scene& scene, const Vec3& a, const Vec3& b, float time) {
    const Vec3 d = b - a;
    const float len = length(d);
    if (!(len > 0.f)) return true;
    const Vec3 w = d / len;
    return scene.occluded(Ray{a + w * (1e-4f * len), w, len * (1.f - 2e-4f)}, {}, time);
}

/// A light point sampled for the chain over one ball and the chain's roots towards it: the
/// part both chains (this one, render/reflection_nee.h) share.
struct ChainLightSample {
    Vec3 y, n_y;
    float p_choice = 0.f;  ///< P_s·P_l·p_A(y): the strategy's density per unit area at y
    int light = -1;
    bool closed_light = false;  ///< seen from outside, only its outside (a sphere)
    int n = 0;
    SphereChainRoot roots[SphereChain::kMaxRoots];
};

/// Picks a light by power, a point y on it by area, and solves the chain from x over sphere
/// `sphere_index` with `nodes` towards y; `p_sphere`: the probability with which this chain
/// and ball were chosen. False when nothing can contribute.
inline bool sample_chain_light(const Scene& scene, int sphere_index, const SphereChainNodes& nodes, const Vec3& x,
                               float p_sphere, float u_light, float u1, float u2, ChainLightSample& out) {
    const Sphere& ball = scene.spheres[static_cast<std::size_t>(sphere_index)];
    float choice = 0.f;
    const int light = out.light = scene.sphere_chains.light_choice.sample(u_light, choice);
    float pdf_area = 0.f;
    if (!caustic_light_sample(scene, sphere_index, light, u1, u2, out.y, out.n_y, pdf_area)) return false;
    const SphereChain chain(DVec3(x), DVec3(ball.center), ball.radius, nodes, DVec3(out.y));
    out.n = chain.solve(out.roots);
    out.closed_light = light_is_closed(scene.lights[static_cast<std::size_t>(light)]);
    out.p_choice = choice * pdf_area * p_sphere;
    return out.n > 0;
}

/// |dω_x/dA_y| of root r at the sampled light point, 0 when it cannot contribute (a sphere
/// closed light is seen from its outside only, so it must face the arriving ray).
inline float chain_root_area_density(const ChainLightSample& s, const SphereChainRoot& r, CausticNeeBug bug) {
    const float cos_y_signed = dot(s.n_y, r.w_exit.to_float());
    if (s.closed_light && !(cos_y_signed < 0.f)) return 0.f;
    const float cos_y = bug == CausticNeeBug::no_cos_y ? 1.f : std::fabs(cos_y_signed);
    const float dw_dA = static_cast<float>(r.dw_dAperp) * cos_y;
    return dw_dA > 0.f && std::isfinite(dw_dA) ? dw_dA : 0.f;
}

/// The strategy's contribution at vertex `hit` (BSDF `bsdf`, outgoing wo); see the header.
/// u_sphere, u_light: the choices; u1, u2: the point on the light.
[[gnu::noinline]] inline SampledSpectrum sample_caustic_nee(const Scene& scene, const Bsdf& bsdf, const Hit& hit,
                                                            const Vec3& wo, const SampledWavelengths& lambda,
                                                            float time, float u_sphere, float u_light, float u1,
                                                            float u2, CausticNeeBug bug, PathStats& stats) {
    const SphereChains& chains = scene.sphere_chains;
    const int n_spheres = static_cast<int>(chains.caustic_spheres.size());
    const int k = std::min(static_cast<int>(u_sphere * static_cast<float>(n_spheres)), n_spheres - 1);
    const CausticSphere& gs = chains.caustic_spheres[static_cast<std::size_t>(k)];
    ChainLightSample ls;
    if (!sample_chain_light(scene, gs.sphere, *gs.nodes, hit.p,
                            chains.refraction_share / static_cast<float>(n_spheres), u_light, u1, u2, ls))
        return SampledSpectrum(0.f);
    const Vec3 y = ls.y;
    const float p_choice = ls.p_choice;
    const int light = ls.light;
    SampledSpectrum sum(0.f);
    for (int i = 0; i < ls.n; ++i) {
        const SphereChainRoot& r = ls.roots[i];
        const Vec3 wx = r.wx.to_float();
        const float dw_dA = chain_root_area_density(ls, r, bug);
        if (dw_dA == 0.f) continue;
        const SampledSpectrum f_cos = bsdf_eval(bsdf, wo, wx, hit.ns, lambda, TransportMode::radiance);
        if (f_cos.is_zero()) continue;
        const float t_in = 1.f - fresnel_dielectric(static_cast<float>(r.cos_in), gs.eta);
        const float t_out = 1.f - fresnel_dielectric(static_cast<float>(r.cos_t), 1.f / gs.eta);
        if (!(t_in * t_out > 0.f)) continue;
        const Vec3 entry = r.entry.to_float(), exit = r.exit.to_float();
        stats.rays += 3;
        const Ray to_entry = spawn_ray_to(hit, entry);
        if (dot(to_entry.d, wx) < 0.99f) continue;  // x within rounding of the sphere: no defined segment
        if (scene.occluded(to_entry, {}, time) || caustic_segment_blocked(scene, entry, exit, time) ||
            caustic_segment_blocked(scene, exit, y, time))
            continue;
        const float p_snee = p_choice / dw_dA;
        const float p_chain = bsdf_pdf(bsdf, wo, wx, hit.ns, lambda.lambda[0]) * t_in * t_out;
        const SampledSpectrum kt = gs.kt.sample(lambda);
        const SampledSpectrum Le =
            light_emitted(scene.lights[static_cast<std::size_t>(light)], y, ls.n_y, -r.w_exit.to_float(), lambda);
        sum += f_cos * kt * kt * Le * (t_in * t_out * power_heuristic(p_snee, p_chain) / p_snee);
    }
    return sum;
}

/// What the path loop remembers of a BSDF-sampled path that may be a caustic chain: the
/// non-delta vertex x, the direction and density it left with, and how far along the chain
/// x → in → out → emitter it is.
struct CausticChainState {
    /// reflected: x → reflected off a sphere of SphereChains::reflecting_spheres
    /// (render/reflection_nee.h).
    enum Stage : std::uint8_t { none, left_x, inside, out, reflected };
    Stage stage = none;
    /// Index in SphereChains::caustic_spheres once inside (reflecting_spheres once reflected).
    int sphere = -1;
    /// The wavelengths' state at x before it sampled (the reflection's lobe choice is taken
    /// over the wavelengths live there: render/reflection_nee.h).
    bool terminated_at_x = false;
    Vec3 x, wx;
    float pdf_x = 0.f;

    /// Index in SphereChains::caustic_spheres of the sphere `hit` is on, or −1.
    static int caustic_sphere_at(const Scene& scene, const Hit& hit) {
        return index_at(scene.sphere_chains.caustic_spheres, hit);
    }
    /// Index in SphereChains::reflecting_spheres of the sphere `hit` is on, or −1.
    static int reflecting_sphere_at(const Scene& scene, const Hit& hit) {
        return index_at(scene.sphere_chains.reflecting_spheres, hit);
    }

private:
    /// Index of the entry of `spheres` (each naming a sphere of the scene) that `hit` is on, or −1.
    template <class Entries>
    static int index_at(const Entries& spheres, const Hit& hit) {
        if (hit.prim.kind() != ShapeKind::sphere) return -1;
        for (std::size_t i = 0; i < spheres.size(); ++i)
            if (static_cast<std::uint32_t>(spheres[i].sphere) == hit.prim.index()) return static_cast<int>(i);
        return -1;
    }
};

/// The root of the chain from s.x over `ball` to hit.p that the path took (its direction
/// within float rounding of s.wx: roots of one configuration lie far apart except at a fold,
/// where the weight hardly matters) and its density |dω_x/dA_y|; false when the solver does
/// not return it (the BSDF side then keeps weight 1).
inline bool matched_chain_root(const CausticChainState& s, const Sphere& ball, const SphereChainNodes& nodes,
                               const Hit& hit, SphereChainRoot& root, float& dw_dA) {
    const SphereChain chain(DVec3(s.x), DVec3(ball.center), ball.radius, nodes, DVec3(hit.p));
    SphereChainRoot roots[SphereChain::kMaxRoots];
    const int n = chain.solve(roots);
    const int i = SphereChain::find_matching_root(roots, n, DVec3(s.wx), 1e-3);
    if (i < 0) return false;
    root = roots[i];
    dw_dA = static_cast<float>(root.dw_dAperp) * std::fabs(dot(hit.n, root.w_exit.to_float()));
    return dw_dA > 0.f && std::isfinite(dw_dA);
}

/// The BSDF side's MIS weight of emission found along a chain x → in → out → `hit` (light
/// `light`): see the header. 1 when the strategy could not have produced this path.
[[gnu::noinline]] inline float caustic_emission_weight(const Scene& scene, const CausticChainState& s, const Hit& hit,
                                                       int light, CausticNeeBug bug) {
    if (bug == CausticNeeBug::no_bsdf_side_weight) return 1.f;
    const SphereChains& chains = scene.sphere_chains;
    const float choice = chains.light_choice.probability(light);
    if (!(choice > 0.f)) return 1.f;
    const CausticSphere& gs = chains.caustic_spheres[static_cast<std::size_t>(s.sphere)];
    const Sphere& glass = scene.spheres[static_cast<std::size_t>(gs.sphere)];
    const float pdf_area = caustic_light_area_pdf(scene, gs.sphere, light, hit.p);
    if (!(pdf_area > 0.f)) return 1.f;
    SphereChainRoot r{};
    float dw_dA = 0.f;
    if (!matched_chain_root(s, glass, *gs.nodes, hit, r, dw_dA)) return 1.f;
    const float t_in = 1.f - fresnel_dielectric(static_cast<float>(r.cos_in), gs.eta);
    const float t_out = 1.f - fresnel_dielectric(static_cast<float>(r.cos_t), 1.f / gs.eta);
    const float p_snee =
        choice * pdf_area * (chains.refraction_share / static_cast<float>(chains.caustic_spheres.size())) / dw_dA;
    return power_heuristic(s.pdf_x * t_in * t_out, p_snee);
}

}  // namespace spt
