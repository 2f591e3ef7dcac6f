#include "render/sphere_chains.h"

#include "geometry/sphere_caustics.h"
#include "scene/scene.h"

namespace spt {

SphereChains SphereChains::prepare(const Scene& scene) {
    SphereChains c;
    if (scene.effects.media) return c;  // the volumetric path tracer does not use them
    const Spectrum zero(SpectrumSource::constant(0.0), SpectralResolution{});
    const Spectrum one(SpectrumSource::constant(1.0), SpectralResolution{});
    for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
        const Sphere& s = scene.spheres[i];
        const Material& m = scene.materials[s.material];
        if (s.light >= 0 || m.textured || !(s.radius > 0.f)) continue;
        // The reflection chain: a delta reflection lobe whose reflectance the strategy knows.
        ReflectingSphere r;
        r.sphere = static_cast<int>(i);
        if (const LobeMixBsdf* b = std::get_if<LobeMixBsdf>(&m.bsdf)) {
            const bool fresnel = b->has_transmission() && b->eta.is_constant() && b->eta.eval(560.f) > 1.f;
            if ((b->has_mirror() || fresnel) && (!b->has_transmission() || fresnel)) {
                r.eta = fresnel ? b->eta.eval(560.f) : 1.f;
                r.kd = b->kd, r.ks = b->ks, r.kt = b->kt;
                r.has_kd = b->has_diffuse(), r.has_kt = fresnel;
                c.reflecting_spheres.push_back(r);
            }
        } else if (const DielectricBsdf* d = std::get_if<DielectricBsdf>(&m.bsdf)) {
            if (d->ggx.is_smooth() && !d->film.present() && !d->is_dispersive() && d->eta.eval(560.f) > 1.f) {
                r.eta = d->eta.eval(560.f);
                r.kd = zero, r.ks = zero, r.kt = one;
                r.has_kt = true;
                c.reflecting_spheres.push_back(r);
            }
        }
        CausticSphere g;
        g.sphere = static_cast<int>(i);
        if (const LobeMixBsdf* b = std::get_if<LobeMixBsdf>(&m.bsdf)) {
            if (b->has_diffuse() || b->has_mirror() || !b->has_transmission() || !b->eta.is_constant()) continue;
            g.eta = b->eta.eval(560.f);
            g.kt = b->kt;
        } else if (const DielectricBsdf* d = std::get_if<DielectricBsdf>(&m.bsdf)) {
            if (!d->ggx.is_smooth() || d->film.present() || d->is_dispersive()) continue;
            g.eta = d->eta.eval(560.f);
            g.kt = Spectrum(SpectrumSource::constant(1.0), SpectralResolution{});
        } else {
            continue;
        }
        if (!(g.eta > 1.f)) continue;  // the solver's contract (η = 1: no refraction; < 1: not handled)
        g.nodes = std::make_shared<const SphereChainNodes>(g.eta);
        c.caustic_spheres.push_back(g);
    }
    if (!c.active()) return c;
    std::vector<float> power(scene.lights.size(), 0.f);
    bool any = false;
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
        if (scene.light_textured(static_cast<int>(i))) continue;
        const Light& light = scene.lights[i];
        if (light_has_area_facing(light)) {
            power[i] = light_power(light);
            any |= power[i] > 0.f;
        }
    }
    if (!any) return SphereChains{};
    if (!c.reflecting_spheres.empty())
        c.reflection_nodes = std::make_shared<const SphereChainNodes>(SphereChainNodes::reflection());
    // With both chains, one vertex in ten samples the reflection: the strategy's main gain is
    // the MIS weight it lends the BSDF-found reflections off the small lights (the fireflies),
    // which a rare sample already gives, and the refraction chain keeps most of its samples.
    // Measured (256², 64 spp, seeds 1-4): relMSE × rays on scenes with a glass ball and a
    // plastic one fell steadily from share 0.5 to 0.97 (0.9 within 1 % of 0.97; sampling
    // both chains at every vertex cost 1.6x the rays); 0.9 leaves more to scenes whose
    // reflections carry more of the light.
    c.refraction_share = c.reflecting_spheres.empty() ? 1.f : c.caustic_spheres.empty() ? 0.f : 0.9f;
    c.light_choice.build(power);
    return c;
}

}  // namespace spt
